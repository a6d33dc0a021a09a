// Every command's --help states a numeric option's limits in one spelling,
// cli/numeric_options.cpp's numeric_limits_text: "whole number ≥ 1 and ≤ 4096",
// "number > 0 and ≤ 3600". CLI11's own spellings ("FLOAT in [0 - 0.5]",
// "POSITIVE", "NONNEGATIVE") and older ones ("from A to B", "below 2^64")
// must not appear, and no numeric option may carry a validator in another form.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.h"

namespace {

using namespace rayverify::test_support;

std::string help_of(const std::string& command) {
    // Wide enough that no option line wraps between its type and its limits.
    const command_result help = run_shell("COLUMNS=400 " + std::string(RAYVERIFY_CLI) + " " + command + " --help");
    EXPECT_EQ(help.exit_code, 0) << command << " --help:\n" << help.output;
    return help.output;
}

// The names under a help text's "Subcommands:" heading.
std::vector<std::string> subcommands_in(const std::string& help) {
    std::vector<std::string> names;
    std::istringstream lines(help);
    bool in_list = false;
    static const std::regex entry(R"(^  ([a-z][a-z-]*)\s)");
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("Subcommands:", 0) == 0) in_list = true;
        std::smatch match;
        if (in_list && std::regex_search(line, match, entry)) names.push_back(match[1]);
    }
    return names;
}

std::vector<std::string> every_command() {
    std::vector<std::string> commands;
    for (const std::string& name : subcommands_in(help_of(""))) {
        commands.push_back(name);
        for (const std::string& sub : subcommands_in(help_of(name))) commands.push_back(name + " " + sub);
    }
    return commands;
}

TEST(HelpText, EveryNumericOptionStatesItsLimitsInOneSpelling) {
    static const std::regex numeric_type(R"((^|\s)(INT|UINT|FLOAT|NUMBER):(\S.*))");
    static const std::regex one_spelling(R"(^(whole number|number) (≥|>) \S+ and (≤|<) \S+)");
    static const std::regex other_spelling(
        R"(\bin \[[^\]]* - |POSITIVE|NONNEGATIVE|whole number from |below 2\^64|≥ \S+ and ≤ \S+ and)");
    const std::vector<std::string> commands = every_command();
    ASSERT_GE(commands.size(), 14u) << "the command list was not read from rayverify --help";
    std::size_t limited_options = 0;
    for (const std::string& command : commands) {
        std::istringstream lines(help_of(command));
        for (std::string line; std::getline(lines, line);) {
            EXPECT_FALSE(std::regex_search(line, other_spelling))
                << "rayverify " << command << " --help spells a range another way:\n" << line;
            std::smatch match;
            if (!std::regex_search(line, match, numeric_type)) continue;
            ++limited_options;
            const std::string limits = match[3];
            EXPECT_TRUE(std::regex_search(limits, one_spelling))
                << "rayverify " << command << " --help: a numeric option's limits not as numeric_limits_text "
                << "spells them:\n" << line;
        }
    }
    EXPECT_GE(limited_options, 20u) << "fewer numeric options with limits than the commands have";
}

}  // namespace
