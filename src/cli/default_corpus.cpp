#include <filesystem>
#include <string>

#include "cli/commands.h"

namespace rayverify::cli {

std::string default_corpus() {
    namespace fs = std::filesystem;
    // RAYVERIFY_INSTALLED_CORPUS is the data directory relative to the
    // installed executable's directory ("../share/rayverify/corpus"); a build
    // tree has nothing there, so it falls back to the source tree's corpus.
    std::error_code error;
    const fs::path executable = fs::read_symlink("/proc/self/exe", error);
    if (!error) {
        const fs::path installed = (executable.parent_path() / RAYVERIFY_INSTALLED_CORPUS).lexically_normal();
        if (fs::is_directory(installed, error)) return installed.string();
    }
    return RAYVERIFY_DEFAULT_CORPUS;
}

}  // namespace rayverify::cli
