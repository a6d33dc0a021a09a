// Running the rayverify executable, or any shell command, from a test, and
// reading back the files it wrote. RAYVERIFY_CLI is defined for every test
// target by tests/CMakeLists.txt.
#pragma once

#include <gtest/gtest.h>
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

// A fresh directory under the system's temporary directory named after
// `stem` and the running GoogleTest test, removed again on destruction.
class scratch_directory {
public:
    explicit scratch_directory(const std::string& stem)
        : path_(std::filesystem::temp_directory_path() /
                (stem + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~scratch_directory() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    scratch_directory(const scratch_directory&) = delete;
    scratch_directory& operator=(const scratch_directory&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace rayverify::test_support
