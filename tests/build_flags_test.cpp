// The floating-point semantics are part of what rayverify measures: every
// file this build compiles (the library, the CLI, the tests, the plugins and
// programs they run) is compiled with -ffp-contract=off -fno-fast-math
// -fno-tree-slp-vectorize, as usage requirements of the targets it links
// (CMakeLists.txt), except the targets that are about other semantics and say
// so with flags of their own. Read from the build's compile_commands.json.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

// Targets built on purpose as an FMA or fast-math compiler would build them
// (tests/CMakeLists.txt): their last word on contraction must be "fast".
const std::vector<std::string> other_semantics = {"/naive_c_fast.dir/", "/robust_fma_plugin_"};
// Built on purpose as an engine's Release build compiles (-O3, the SLP
// vectoriser on: tools/port_timing/): contraction still off, no fast math.
const std::vector<std::string> vectorised_on_purpose = {"/port_timing_release.dir/"};

std::vector<std::string> words_of(const std::string& command) {
    std::istringstream in(command);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

struct semantics {
    std::string contraction;  // the last -ffp-contract=X's X, empty when none
    bool fast_math = false;   // -ffast-math after the last -fno-fast-math
    bool slp_off = false;     // -fno-tree-slp-vectorize after the last -ftree-slp-vectorize
};

semantics semantics_of(const std::vector<std::string>& words) {
    semantics s;
    for (const std::string& w : words) {
        if (w.rfind("-ffp-contract=", 0) == 0) s.contraction = w.substr(14);
        if (w == "-ffast-math") s.fast_math = true;
        if (w == "-fno-fast-math") s.fast_math = false;
        if (w == "-fno-tree-slp-vectorize") s.slp_off = true;
        if (w == "-ftree-slp-vectorize") s.slp_off = false;
    }
    return s;
}

TEST(BuildFlags, EveryCompiledFileHasTheFloatingPointSemanticsOrStatesItsOwn) {
    std::ifstream in(RAYVERIFY_COMPILE_COMMANDS);
    ASSERT_TRUE(in) << "no " << RAYVERIFY_COMPILE_COMMANDS << " (CMAKE_EXPORT_COMPILE_COMMANDS)";
    const nlohmann::json commands = nlohmann::json::parse(in);
    ASSERT_TRUE(commands.is_array());
    std::size_t checked = 0, exempt = 0, library = 0, cli = 0, tests = 0, release_builds = 0;
    for (const auto& entry : commands) {
        const std::string command = entry.value("command", std::string());
        const std::string output = entry.value("output", std::string());
        const std::string file = entry.value("file", std::string());
        const semantics s = semantics_of(words_of(command));
        const bool other = std::any_of(other_semantics.begin(), other_semantics.end(), [&](const std::string& m) {
            return output.find(m) != std::string::npos || command.find(m) != std::string::npos;
        });
        if (other) {
            ++exempt;
            EXPECT_EQ(s.contraction, "fast") << file << " is built as an FMA compiler would build it:\n" << command;
            continue;
        }
        ++checked;
        // The library and the CLI are unity builds (CMakeLists.txt): their
        // files reach the compiler through unity sources, which carry the flags.
        const std::string where = file + " " + output + " " + command;
        library += where.find("/rayverify.dir/") != std::string::npos;
        cli += where.find("/rayverify_cli.dir/") != std::string::npos;
        tests += where.find("_test.dir/") != std::string::npos;
        EXPECT_EQ(s.contraction, "off") << file << " is compiled without -ffp-contract=off:\n" << command;
        EXPECT_FALSE(s.fast_math) << file << " is compiled with fast math:\n" << command;
        const bool vectorised = std::any_of(vectorised_on_purpose.begin(), vectorised_on_purpose.end(),
                                            [&](const std::string& m) { return command.find(m) != std::string::npos; });
        if (vectorised) {
            EXPECT_FALSE(s.slp_off) << file << " is the Release build of the ports, vectoriser on:\n" << command;
            ++release_builds;
        } else {
            EXPECT_TRUE(s.slp_off) << file << " is compiled without -fno-tree-slp-vectorize:\n" << command;
        }
    }
    EXPECT_GT(library, 0u) << "the library is in compile_commands.json";
    EXPECT_GT(cli, 0u) << "the CLI is in compile_commands.json";
    EXPECT_GT(tests, 50u) << "the tests are in compile_commands.json";
    EXPECT_GT(exempt, 0u) << "the FMA fixtures are gone: update other_semantics";
    EXPECT_EQ(release_builds, 1u) << "the ports' Release build is gone: update vectorised_on_purpose";
}

}  // namespace
