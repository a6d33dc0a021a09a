// Running the rayverify executable, or any shell command, from a test, and
// reading back the files it wrote. RAYVERIFY_CLI is defined for every test
// target by tests/CMakeLists.txt.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rayverify::test_support {

struct command_result {
    int exit_code = -1;  // -1 when the command could not run or did not exit normally
    std::string output;  // stdout and stderr together
};

inline command_result run_shell(const std::string& command) {
    command_result r;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buffer{};
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) r.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

inline command_result run_cli(const std::string& arguments) {
    return run_shell(std::string(RAYVERIFY_CLI) + " " + arguments);
}

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace rayverify::test_support
