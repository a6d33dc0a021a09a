#include "core/installed_data.h"

namespace rayverify {

std::filesystem::path installed_file(std::string_view installed_dir, std::string_view name,
                                     const std::filesystem::path& build_tree_path) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path executable = fs::read_symlink("/proc/self/exe", error);
    if (!error) {
        const fs::path installed = (executable.parent_path() / installed_dir / name).lexically_normal();
        if (fs::exists(installed, error)) return installed;
    }
    return build_tree_path;
}

std::filesystem::path data_file(std::string_view name, const std::filesystem::path& build_tree_path) {
    // RAYVERIFY_INSTALLED_DATA is the data directory relative to the installed
    // executable's directory ("../share/rayverify").
    return installed_file(RAYVERIFY_INSTALLED_DATA, name, build_tree_path);
}

}  // namespace rayverify
