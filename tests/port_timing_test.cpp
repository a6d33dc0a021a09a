// tools/port_timing/: the engine ports timed in rayverify's build and in an
// engine's Release build. Its list of ports must be the registry's (both
// expand intersectors/variants.def), and the two builds must answer alike on
// every port, or the Release timing would be of other code.
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "intersectors/registry.h"
#include "support/process.h"

namespace {

using rayverify::test_support::run_shell;

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

// "name precision" → checksum, from a timing run's lines.
std::map<std::string, std::string> checksums_of(const std::string& output) {
    std::map<std::string, std::string> out;
    for (const std::string& line : lines_of(output)) {
        std::istringstream in(line);
        std::string name, precision, ns, checksum;
        in >> name >> precision >> ns >> checksum;
        EXPECT_FALSE(checksum.empty()) << "not a timing line: " << line;
        out[name + " " + precision] = checksum;
    }
    return out;
}

TEST(PortTiming, ListsTheRegistrysEnginePorts) {
    std::vector<std::string> registry;
    for (const rayverify::variant& v : rayverify::builtin_variants())
        if (!v.build.empty()) registry.push_back(v.name);
    const auto listed = run_shell(std::string(RAYVERIFY_PORT_TIMING_RELEASE) + " --list");
    ASSERT_EQ(listed.exit_code, 0) << listed.output;
    EXPECT_EQ(lines_of(listed.output), registry);
}

TEST(PortTiming, TheReleaseBuildAnswersAsRayverifysBuild) {
    const std::string options = " --cases 300 --seconds 0.001";
    const auto ours = run_shell(std::string(RAYVERIFY_PORT_TIMING_RAYVERIFY) + options);
    const auto release = run_shell(std::string(RAYVERIFY_PORT_TIMING_RELEASE) + options);
    ASSERT_EQ(ours.exit_code, 0) << ours.output;
    ASSERT_EQ(release.exit_code, 0) << release.output;
    const auto a = checksums_of(ours.output), b = checksums_of(release.output);
    EXPECT_GT(a.size(), 10u);  // naive and every port in each precision it has
    EXPECT_EQ(a, b);
}

TEST(PortTiming, ABadOptionIsExitTwo) {
    for (const char* options : {" --cases 0", " --seconds -1", " --frobnicate 3", " --cases"}) {
        const auto r = run_shell(std::string(RAYVERIFY_PORT_TIMING_RAYVERIFY) + options);
        EXPECT_EQ(r.exit_code, 2) << options << ": " << r.output;
        EXPECT_NE(r.output.find("usage: port_timing"), std::string::npos) << r.output;
    }
}

}  // namespace
