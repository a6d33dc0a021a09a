// robust_sphere.h in a C++17 project (issue 47: the engines that need it build
// as C++17 or older): each query level and tier built -std=c++17
// -ffp-contract=off by the project's compiler and by clang into a plugin
// (tests/plugin_fixtures/robust_plugin.cpp, tests/CMakeLists.txt), audited
// through the CLI on the shipped corpus and every edge family, gives exactly
// the verdicts and root errors of rayverify's own C++20 build; and so does the
// C interface (robust_sphere_c.h) called from C compiled with -ffast-math,
// its one C++ translation unit compiled strictly as its own object.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
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

// The audit's results of `plugins` beside the built-in variants they stand
// for: named `<builtin><suffix>`, each must give the built-in's figures.
void expect_library_answers(const std::vector<std::pair<std::string, std::string>>& plugins_and_names,
                            const char* scratch_name) {
    test_support::scratch_directory scratch(scratch_name);
    std::string arguments = "audit --corpus " RAYVERIFY_CORPUS_DIR " --corpus " RAYVERIFY_CORPUS_DIR "/edge --report " +
                            scratch.path().string() + " --threads 2";
    for (const char* builtin : builtin_of_query) arguments += std::string(" --variant ") + builtin;
    for (const auto& [path, name] : plugins_and_names) arguments += " --plugin " + path;
    const test_support::command_result ran = run_cli(arguments);
    ASSERT_TRUE(ran.exit_code == 0 || ran.exit_code == 1) << ran.output;
    // A plugin linked with -ffast-math would run in FTZ+DAZ, set at load, and the audit would say so.
    EXPECT_EQ(ran.output.find("FTZ"), std::string::npos) << ran.output;
    const json report = json::parse(test_support::read_text(scratch.path() / "report.json"));
    for (const auto& [path, name] : plugins_and_names) {
        const std::string builtin = name.substr(0, name.find("_cxx17_") != std::string::npos ? name.find("_cxx17_")
                                                                                               : name.find("_c_fastmath"));
        for (const char* precision : {"float", "double"}) {
            SCOPED_TRACE(name + "/" + precision);
            const json& built = result_for(report, name, precision);
            const json& library = result_for(report, builtin, precision);
            ASSERT_TRUE(built.contains("verdicts") && library.contains("verdicts"));
            EXPECT_EQ(built.at("cases"), library.at("cases"));
            EXPECT_EQ(built.at("verdicts"), library.at("verdicts"));
            EXPECT_EQ(built.at("disagreements"), library.at("disagreements"));
            for (const char* figure : {"near_root_ulp", "far_root_ulp", "scale_error_radius", "by_family"}) {
                ASSERT_TRUE(library.contains(figure)) << figure;
                EXPECT_EQ(built.at(figure), library.at(figure)) << figure;
            }
            // The library's own disagreements: none but the documented nearest hit
            // past the float range (docs/robust_sphere.md).
            EXPECT_LE(library.at("disagreements").get<int>(), 1);
        }
    }
}

TEST(RobustCxx17, EveryQueryBuiltAsCxx17WithEachCompilerAnswersAsTheLibrary) {
    std::vector<std::pair<std::string, std::string>> plugins;
    for (const std::string& path : plugin_paths()) {
        // robust_cxx17_<compiler>_<query>.so
        const std::string file = std::filesystem::path(path).stem().string();
        const std::string compiler = file.substr(std::string("robust_cxx17_").size(),
                                                 file.rfind('_') - std::string("robust_cxx17_").size());
        const int query = std::stoi(file.substr(file.rfind('_') + 1));
        plugins.emplace_back(path, std::string(builtin_of_query[query]) + "_cxx17_" + compiler);
    }
    ASSERT_GE(plugins.size(), 5u);  // five queries per compiler: gcc, and clang where installed
    expect_library_answers(plugins, "rayverify_robust_cxx17");
}

TEST(RobustC, TheCInterfaceCalledFromFastMathCAnswersAsTheLibrary) {
    std::vector<std::pair<std::string, std::string>> plugins;
    std::istringstream list(RAYVERIFY_ROBUST_C_PLUGINS);
    for (std::string path; std::getline(list, path, ':');) {
        const int query = path[path.size() - 4] - '0';  // robust_c_fastmath_<query>.so
        plugins.emplace_back(path, std::string(builtin_of_query[query]) + "_c_fastmath");
    }
    ASSERT_EQ(plugins.size(), 3u);
    expect_library_answers(plugins, "rayverify_robust_c");
}

}  // namespace
}  // namespace rayverify
