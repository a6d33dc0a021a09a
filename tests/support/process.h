// Running the rayverify executable, or any shell command, from a test, and
// reading back the files it wrote. RAYVERIFY_CLI is defined for every test
// target by tests/CMakeLists.txt.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

// A fresh directory under the system's temporary directory, named after
// `stem`, the running GoogleTest test and this process, and removed with
// everything in it on destruction (permissions a test took away are given back
// first). Every test that writes files writes them in one.
class scratch_directory {
public:
    explicit scratch_directory(const std::string& stem)
        : path_(std::filesystem::temp_directory_path() / (stem + "_" + test_name() + "_" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~scratch_directory() {
        namespace fs = std::filesystem;
        std::error_code ignored;
        fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
        for (const auto& entry : fs::recursive_directory_iterator(path_, ignored))
            fs::permissions(entry.path(), fs::perms::owner_all, fs::perm_options::add, ignored);
        fs::remove_all(path_, ignored);
    }
    scratch_directory(const scratch_directory&) = delete;
    scratch_directory& operator=(const scratch_directory&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }

private:
    // The running test's name, one path component ("Name/0" of a parameterised test as "Name_0").
    static std::string test_name() {
        const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = info != nullptr ? info->name() : "outside_a_test";
        std::replace(name.begin(), name.end(), '/', '_');
        return name;
    }

    std::filesystem::path path_;
};

}  // namespace rayverify::test_support
