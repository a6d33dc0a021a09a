// GoogleTest assertion for a user's test suite: "this intersector, on this
// corpus, under this baseline's policy, has no numeric regressions".
//
//     #include <rayverify/testing/gtest_gate.h>
//     TEST(MySphere, NoNumericRegressions) {
//         EXPECT_NO_NUMERIC_REGRESSIONS(my_variant, "gate/baseline.txt", {"corpus/uniform.txt", "corpus/far_sphere.txt"});
//     }
//
// On failure it prints the gate's diff ("mine/double far_sphere: false_miss
// 0 → 24") and the first failing cases as corpus lines to paste into a
// regression corpus. With RAYVERIFY_UPDATE_BASELINE=1 in the environment it
// writes the baseline instead (creating it if needed) and passes, as
// `rayverify gate --update` does. Header only: it needs GoogleTest, which the
// rayverify library does not link.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "compare/gate.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "report/gate_report.h"

namespace rayverify::gate_testing {

inline ::testing::AssertionResult has_no_numeric_regressions(const variant& subject,
                                                             const std::vector<std::filesystem::path>& corpus,
                                                             const std::filesystem::path& baseline_file,
                                                             std::size_t examples = 3) {
    try {
        const char* update_flag = std::getenv("RAYVERIFY_UPDATE_BASELINE");
        const bool update = update_flag && std::string(update_flag) == "1";
        baseline base = new_baseline();
        if (std::filesystem::exists(baseline_file)) {
            std::ifstream in(baseline_file, std::ios::binary);
            std::ostringstream text;
            text << in.rdbuf();
            base = parse_baseline(baseline_file.string(), text.str());
        } else if (!update) {
            return ::testing::AssertionFailure() << baseline_file.string()
                                                 << ": no such baseline; run with RAYVERIFY_UPDATE_BASELINE=1 "
                                                    "to create it";
        }
        const std::vector<corpus_case> cases = read_corpus(corpus);
        const variant subjects[] = {subject};
        const gate_run run = run_gate(cases, targets_for(subjects), base, examples);
        if (update) {
            write_file_atomically(baseline_file, format_baseline(updated_baseline(base, run.current)));
            return ::testing::AssertionSuccess() << "baseline written: " << baseline_file.string();
        }
        if (run.result.passed()) return ::testing::AssertionSuccess() << render_gate_text(run, cases);
        return ::testing::AssertionFailure() << subject.name << " regressed against " << baseline_file.string()
                                             << ":\n"
                                             << render_gate_text(run, cases);
    } catch (const input_error& e) {
        return ::testing::AssertionFailure() << e.what();
    }
}

}  // namespace rayverify::gate_testing

// The corpus comes last so that a braced list of paths may contain commas.
#define EXPECT_NO_NUMERIC_REGRESSIONS(subject, baseline_file, ...) \
    EXPECT_TRUE(::rayverify::gate_testing::has_no_numeric_regressions((subject), __VA_ARGS__, (baseline_file)))
#define ASSERT_NO_NUMERIC_REGRESSIONS(subject, baseline_file, ...) \
    ASSERT_TRUE(::rayverify::gate_testing::has_no_numeric_regressions((subject), __VA_ARGS__, (baseline_file)))
