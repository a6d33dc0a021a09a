// explain's steps: every built-in variant's own code run on traced scalars
// (intersectors/traced.h, intersectors/traced_variants.h) names its
// intermediates, computed bit for bit as the plain run computes them and
// beside the exact value of the same expression (oracle/ideal_arithmetic.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "intersectors/traced_variants.h"
#include "oracle/ideal_arithmetic.h"
#include "support/process.h"

namespace rayverify {
namespace {

using test_support::command_result;
using test_support::run_cli;

// A line 4100 radii from a unit sphere, missing its centre by 0.56 r: in
// float, naive's b² and 4aC are both 4100²·4 and Δ = b² − 4aC cancels to 0
// while the exact Δ is 2.75.
const ray_sphere<double> far_line{{0.5, 0.25, 0}, {0, 0, 1}, {0, 0, 4100}, 1};

template <class T>
std::vector<traced_step> steps_of(trace_fn<T> run, const ray_sphere<double>& g, exact_arithmetic& ideal) {
    trace_session session(ideal);
    run(rounded_to<T>(g), T(0), std::numeric_limits<T>::infinity());
    return session.steps;
}

const traced_step* find_step(const std::vector<traced_step>& steps, const std::string& name) {
    for (const traced_step& s : steps)
        if (s.name == name) return &s;
    return nullptr;
}

// The step that decides hit or miss, as each formula names it.
const std::set<std::string> discriminant_names{"Δ",  "Δ′",      "d²",        "d2",      "d",      "det",
                                               "discrim", "r2 − l2", "inters_d2", "Δ low"};

TEST(ExplainSteps, EveryBuiltinVariantNamesItsDiscriminantComputedAndExact) {
    for (const variant& v : builtin_variants()) {
        const variant_trace* trace = find_builtin_trace(v.name);
        ASSERT_NE(trace, nullptr) << v.name << " has no trace";
        for (precision p : {precision::binary32, precision::binary64}) {
            SCOPED_TRACE(v.name + "/" + precision_name(p));
            const bool has_trace = p == precision::binary32 ? trace->in_float != nullptr : trace->in_double != nullptr;
            EXPECT_EQ(has_trace, v.runs_in(p));
            if (!has_trace) continue;
            exact_arithmetic ideal;
            const std::vector<traced_step> steps = p == precision::binary32
                                                       ? steps_of<float>(trace->in_float, far_line, ideal)
                                                       : steps_of<double>(trace->in_double, far_line, ideal);
            const traced_step* discriminant = nullptr;
            for (const traced_step& s : steps)
                if (!discriminant && discriminant_names.count(s.name)) discriminant = &s;
            ASSERT_NE(discriminant, nullptr) << "no discriminant-like step among " << steps.size();
            const step_figures f = ideal.measure(*discriminant);
            EXPECT_TRUE(std::isfinite(discriminant->computed));
            EXPECT_TRUE(std::isfinite(f.exact));
            EXPECT_TRUE(discriminant->digits == 24 || discriminant->digits == 53);
        }
    }
}

TEST(ExplainSteps, NaiveFloatDiscriminantCancelsToZeroWhileTheExactOneIsPositive) {
    exact_arithmetic ideal;
    const std::vector<traced_step> steps = steps_of<float>(find_builtin_trace("naive")->in_float, far_line, ideal);
    const traced_step* discriminant = find_step(steps, "Δ");
    ASSERT_NE(discriminant, nullptr);
    EXPECT_EQ(discriminant->computed, 0.0);
    const step_figures f = ideal.measure(*discriminant);
    EXPECT_EQ(f.exact, 2.75);  // b² − 4aC = 67240000 − 4·16809999.3125
    EXPECT_EQ(f.relative_error, 1.0);
    EXPECT_EQ(f.bits_lost, 24.0);  // all of them
    EXPECT_TRUE(discriminant->subtraction);
    EXPECT_TRUE(std::isinf(discriminant->cancelled));
    // C itself is correctly rounded: its loss only shows once Δ cancels.
    const traced_step* C = find_step(steps, "C");
    ASSERT_NE(C, nullptr);
    EXPECT_EQ(ideal.measure(*C).bits_lost, 0.0);
    EXPECT_EQ(ideal.measure(*C).exact, 16809999.3125);
}

TEST(ExplainSteps, AnExactDifferenceLosesNoBits) {
    exact_arithmetic ideal;
    const std::vector<traced_step> steps = steps_of<double>(find_builtin_trace("naive")->in_double, far_line, ideal);
    for (const char* name : {"f.x", "f.y", "f.z"}) {
        const traced_step* f = find_step(steps, name);
        ASSERT_NE(f, nullptr) << name;
        const step_figures figures = ideal.measure(*f);
        EXPECT_EQ(figures.relative_error, 0.0) << name;
        EXPECT_EQ(figures.bits_lost, 0.0) << name;
        EXPECT_EQ(figures.exact, f->computed) << name;
    }
    EXPECT_EQ(find_step(steps, "f.z")->computed, -4100.0);
}

TEST(ExplainSteps, BitsLostAndCancellationFormulas) {
    EXPECT_EQ(bits_lost(0, 53), 0);
    EXPECT_EQ(bits_lost(0x1p-60, 53), 0);  // within rounding
    EXPECT_EQ(bits_lost(0x1p-43, 53), 10);
    EXPECT_EQ(bits_lost(1, 24), 24);
    EXPECT_EQ(bits_lost(std::numeric_limits<double>::infinity(), 24), 24);
    EXPECT_EQ(cancelled_bits(1024, -1023, 1), 10);
    EXPECT_EQ(cancelled_bits(3, 4, 7), 0);  // same signs: no cancellation
    EXPECT_TRUE(std::isinf(cancelled_bits(5, -5, 0)));
}

// An ideal side that keeps nothing: the computed side alone is checked here.
class computed_only final : public ideal_arithmetic {
public:
    ideal_id exactly(double) override { return 0; }
    ideal_id add(ideal_id, ideal_id) override { return 0; }
    ideal_id subtract(ideal_id, ideal_id) override { return 0; }
    ideal_id multiply(ideal_id, ideal_id) override { return 0; }
    ideal_id divide(ideal_id, ideal_id) override { return 0; }
    ideal_id square_root(ideal_id) override { return 0; }
    ideal_id fused_multiply_add(ideal_id, ideal_id, ideal_id) override { return 0; }
    ideal_id negate(ideal_id) override { return 0; }
    ideal_id absolute(ideal_id) override { return 0; }
    ideal_id arc_tangent2(ideal_id, ideal_id) override { return 0; }
};

// The traced run takes the plain run's path and computes its values bit for
// bit: its answer equals the audited function's on every shipped corpus case.
TEST(ExplainSteps, TracedRunsAnswerBitForBitAsThePlainFunctions) {
    const std::filesystem::path shipped(RAYVERIFY_CORPUS_DIR);
    const std::vector<corpus_case> corpus = read_corpus({shipped, shipped / "edge"});
    ASSERT_FALSE(corpus.empty());
    computed_only ideal;
    const auto check = [&]<class T>(const variant& v, trace_fn<T> run, const ray_sphere<double>& g) {
        if (!run || validity<T>(g) != invalid_reason::none) return;
        const ray_sphere<T> s = rounded_to<T>(g);
        const root_pair<T> plain = run_in(v, s, ray_interval<T>{});
        trace_session session(ideal);
        run(s, T(0), std::numeric_limits<T>::infinity());
        const traced_step* t = find_step(session.steps, "answer t");
        const traced_step* t0 = find_step(session.steps, "answer t0");
        const traced_step* t1 = find_step(session.steps, "answer t1");
        const auto same = [](double traced, T computed) {
            return std::isnan(traced) ? std::isnan(computed) : static_cast<T>(traced) == computed && std::signbit(traced) == std::signbit(computed);
        };
        if (plain.count == 2) {
            ASSERT_TRUE(t0 && t1) << v.name;
            EXPECT_TRUE(same(t0->computed, plain.t0) && same(t1->computed, plain.t1)) << v.name;
        } else if (plain.count == 1 && t) {
            EXPECT_TRUE(same(t->computed, plain.t0)) << v.name;
        } else {
            EXPECT_FALSE(t0 || t1) << v.name;
        }
    };
    std::size_t checked = 0;
    for (const variant& v : builtin_variants()) {
        const variant_trace* trace = find_builtin_trace(v.name);
        if (!trace->what.empty() && v.name.rfind("robust", 0) == 0) continue;  // shows its filter, not its roots
        for (std::size_t i = 0; i < corpus.size(); ++i) {
            SCOPED_TRACE(corpus[i].id);
            check.template operator()<float>(v, trace->in_float, corpus[i].geometry);
            check.template operator()<double>(v, trace->in_double, corpus[i].geometry);
            ++checked;
        }
    }
    EXPECT_GT(checked, 50000u);
}

TEST(ExplainSteps, ExplainPrintsTheStepsAndTheirLegend) {
    const command_result r =
        run_cli("explain 0.5 0.25 0 0 0 1 0 0 4100 1 --variant naive --variant embree4 --precision float");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("    steps:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rcp estimate"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("FRECPE's bits"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("steps: each intermediate"), std::string::npos) << r.output;
    // Δ computed 0, exact 2.75: every bit lost, every bit cancelled.
    const auto delta = r.output.find("      Δ ");
    ASSERT_NE(delta, std::string::npos) << r.output;
    const std::string line = r.output.substr(delta, r.output.find('\n', delta) - delta);
    EXPECT_NE(line.find("2.75"), std::string::npos) << line;
    EXPECT_NE(line.find("all 24"), std::string::npos) << line;
    const command_result quiet =
        run_cli("explain 0.5 0.25 0 0 0 1 0 0 4100 1 --variant naive --precision float --no-steps");
    EXPECT_EQ(quiet.output.find("steps"), std::string::npos) << quiet.output;
}

}  // namespace
}  // namespace rayverify
