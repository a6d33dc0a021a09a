// Files rayverify reads at run time (the shipped corpus, the plot script):
// under share/rayverify beside an installed executable, so that an install to
// any prefix (cmake --install, the .deb) works from any directory; in a build
// tree, where nothing is installed, the source tree's copy.
#pragma once

#include <filesystem>
#include <string_view>

namespace rayverify {

// `name` in the installed data directory (<bindir>/../share/rayverify, as
// configured) when the running executable has one that holds it, else
// `build_tree_path`.
std::filesystem::path data_file(std::string_view name, const std::filesystem::path& build_tree_path);

// The same for a file installed elsewhere: `name` in `installed_dir` (relative
// to the running executable's directory, e.g. "../lib/rayverify/engines")
// when it is there, else `build_tree_path`.
std::filesystem::path installed_file(std::string_view installed_dir, std::string_view name,
                                     const std::filesystem::path& build_tree_path);

}  // namespace rayverify
