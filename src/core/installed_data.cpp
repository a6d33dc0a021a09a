#include "core/installed_data.h"

namespace rayverify {

std::filesystem::path data_file(std::string_view name, const std::filesystem::path& build_tree_path) {
    namespace fs = std::filesystem;
    // RAYVERIFY_INSTALLED_DATA is the data directory relative to the installed
    // executable's directory ("../share/rayverify").
    std::error_code error;
    const fs::path executable = fs::read_symlink("/proc/self/exe", error);
    if (!error) {
        const fs::path installed = (executable.parent_path() / RAYVERIFY_INSTALLED_DATA / name).lexically_normal();
        if (fs::exists(installed, error)) return installed;
    }
    return build_tree_path;
}

}  // namespace rayverify
