// robust_sphere.h in a C++17 project (issue 47: the engines that need it build
// as C++17 or older): each query level and tier built -std=c++17
// -ffp-contract=off by the project's compiler and by clang into a plugin
// (tests/plugin_fixtures/robust_plugin.cpp, tests/CMakeLists.txt), audited
// through the CLI on the shipped corpus and every edge family, gives exactly
// the verdicts and root errors of rayverify's own C++20 build.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.h"
#include "support/report_results.h"

namespace rayverify {
namespace {

using nlohmann::json;
using test_support::result_for;
using test_support::run_cli;

// The plugins' paths, and the built-in variant each one's query is.
std::vector<std::string> plugin_paths() {
    std::vector<std::string> paths;
    std::istringstream list(RAYVERIFY_ROBUST_CXX17_PLUGINS);
    for (std::string path; std::getline(list, path, ':');) paths.push_back(path);
    return paths;
}

const char* const builtin_of_query[] = {"robust", "robust_nearest", "robust_any_hit", "robust_bounded",
                                        "robust_bounded_nearest"};

TEST(RobustCxx17, EveryQueryBuiltAsCxx17WithEachCompilerAnswersAsTheLibrary) {
    const std::vector<std::string> paths = plugin_paths();
    ASSERT_GE(paths.size(), 5u);  // five queries per compiler: gcc, and clang where installed
    test_support::scratch_directory scratch("rayverify_robust_cxx17");
    std::string arguments = "audit --corpus " RAYVERIFY_CORPUS_DIR " --corpus " RAYVERIFY_CORPUS_DIR "/edge --report " +
                            scratch.path().string() + " --threads 2";
    for (const char* builtin : builtin_of_query) arguments += std::string(" --variant ") + builtin;
    for (const std::string& path : paths) arguments += " --plugin " + path;
    const test_support::command_result ran = run_cli(arguments);
    ASSERT_TRUE(ran.exit_code == 0 || ran.exit_code == 1) << ran.output;
    const json report = json::parse(test_support::read_text(scratch.path() / "report.json"));
    for (const std::string& path : paths) {
        // robust_cxx17_<compiler>_<query>.so
        const std::string file = std::filesystem::path(path).stem().string();
        const std::string compiler = file.substr(std::string("robust_cxx17_").size(),
                                                 file.rfind('_') - std::string("robust_cxx17_").size());
        const int query = std::stoi(file.substr(file.rfind('_') + 1));
        const std::string builtin = builtin_of_query[query];
        const std::string name = builtin + "_cxx17_" + compiler;
        for (const char* precision : {"float", "double"}) {
            SCOPED_TRACE(name + "/" + precision);
            const json& cxx17 = result_for(report, name, precision);
            const json& library = result_for(report, builtin, precision);
            ASSERT_TRUE(cxx17.contains("verdicts") && library.contains("verdicts"));
            EXPECT_EQ(cxx17.at("cases"), library.at("cases"));
            EXPECT_EQ(cxx17.at("verdicts"), library.at("verdicts"));
            EXPECT_EQ(cxx17.at("disagreements"), library.at("disagreements"));
            for (const char* figure : {"near_root_ulp", "far_root_ulp", "scale_error_radius", "by_family"}) {
                ASSERT_TRUE(library.contains(figure)) << figure;
                EXPECT_EQ(cxx17.at(figure), library.at(figure)) << figure;
            }
            // The library's own disagreements: none but the documented nearest hit
            // past the float range (docs/robust_sphere.md).
            EXPECT_LE(library.at("disagreements").get<int>(), 1);
        }
    }
}

}  // namespace
}  // namespace rayverify
