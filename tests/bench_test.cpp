// The timing harness's correctness (never its speed): the kernels it times
// are the registry's variants, return exactly what the audited functions
// return, and every row it reports is complete.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <sstream>

#include "bench/far_sphere_sweep.h"
#include "bench/kernels.h"
#include "bench/long_double.h"
#include "bench/oracle_timing.h"
#include "bench/robust_fallback.h"
#include "bench/timing.h"
#include "corpus/generators.h"
#include "intersectors/registry.h"
#include "report/audit_timing_report.h"

namespace rayverify::bench {
namespace {

std::vector<corpus_case> sample_cases() {
    std::vector<corpus_case> out;
    for (const char* family : {"uniform", "far_sphere", "tangent_exact", "on_surface"})
        for (corpus_case& c : generate_family(family, 40, 3)) out.push_back(std::move(c));
    return out;
}

template <class T>
bool same(const root_pair<T>& a, const root_pair<T>& b) {
    const auto bits_equal = [](T x, T y) { return (x == y && std::signbit(x) == std::signbit(y)) || (x != x && y != y); };
    return a.count == b.count && (a.count == 0 || (bits_equal(a.t0, b.t0) && bits_equal(a.t1, b.t1)));
}

TEST(Bench, KernelsAreTheRegistryInOrder) {
    std::vector<std::string> names;
    for_each_kernel([&](std::string_view name, auto) { names.emplace_back(name); });
    std::vector<std::string> registry;
    for (const variant& v : builtin_variants())
        if (v.build.empty()) registry.push_back(v.name);  // engine ports are timed through their functions
    EXPECT_EQ(names, registry);
}

TEST(Bench, KernelsReturnWhatTheAuditedFunctionsReturn) {
    const std::vector<corpus_case> cases = sample_cases();
    for_each_kernel([&](std::string_view name, auto kernel) {
        const variant& v = *find_builtin_variant(name);
        for (const corpus_case& c : cases) {
            const auto f = rounded_to<float>(c.geometry);
            EXPECT_TRUE(same(kernel(f), v.run_float(f))) << name << " float " << c.id;
            EXPECT_TRUE(same(kernel(c.geometry), v.run_double(c.geometry))) << name << " double " << c.id;
        }
    });
}

TEST(Bench, LongDoubleVariantsComputeInLongDouble) {
    const std::vector<variant> variants = long_double_variants();
    std::size_t written_for_long_double = 0;
    for_each_kernel([&](std::string_view, auto kernel) { written_for_long_double += has_long_double<decltype(kernel)>; });
    ASSERT_EQ(variants.size(), written_for_long_double);
    // Every formula (no engine build) has a long double form but robust_sphere.h's variants (float and double only).
    const auto formulas = std::count_if(builtin_variants().begin(), builtin_variants().end(),
                                        [](const variant& v) { return v.build.empty(); });
    EXPECT_EQ(static_cast<std::ptrdiff_t>(written_for_long_double),
              formulas - static_cast<std::ptrdiff_t>(std::size(robust_variant_names)));
    // naive on a far sphere: long double keeps C = f·f − r² that double loses.
    const ray_sphere<double> far{{-1e9, 0, 0}, {1, 0, 0}, {0, 0.5, 0}, 1};
    const root_pair<double> wide = variants[0].run_double(far);
    const root_pair<long double> direct = intersectors::naive(rounded_to<long double>(far));
    EXPECT_EQ(wide.count, direct.count);
    EXPECT_EQ(wide.t0, static_cast<double>(direct.t0));
    EXPECT_FALSE(variants[0].run_float);
}

// A missed audit target says what meeting it would take, from the run's
// parts: the largest parts that would have to go, or, where the parts (each
// a median of its own timings) already sum within the target, that the gap
// is between medians, not a part to remove.
TEST(Bench, MissedAuditTargetSaysWhatMeetingItTakes) {
    audit_timing timing;
    timing.repetitions = 3;
    timing.target_count = 28;
    const auto row = [](std::string family, double ratio, audit_parts parts) {
        audit_timing_row r;
        r.family = std::move(family);
        r.cases = 500;
        r.naive_ns = 2.5;
        r.audit_ns = ratio * 2.5;
        r.audit_ratio = ratio;
        r.per_case_ratio = 1.5;
        r.per_case_bytes = 200;
        r.parts = parts;
        return r;
    };
    // Parts summing to 67.9x of 76.5x, against 40x: figures and verdicts go.
    timing.rows.push_back(row("uniform", 76.5, {5.2, 1.6, 18.1, 17.3, 14.8, 10.9}));
    // Parts summing to 98.9x of 101.2x, against 100x: no part need go.
    timing.rows.push_back(row("near_tangent", 101.2, {3.0, 6.2, 21.9, 25.4, 14.1, 28.3}));
    timing.rows.push_back(row("all", 90, {4, 4, 20, 20, 14, 20}));
    const std::string text = audit_timing_text(timing);
    EXPECT_NE(text.find("audit / naive double, uniform                           76.50x  target <= 40x  MISSED\n"
                        "      needs 36.5x of 76.5x gone (48%); removing the largest parts until the rest meets it "
                        "takes verdicts (18.1x) + figures (17.3x), leaving 32.5x\n"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("audit / naive double, near_tangent                     101.20x  target <= 100x  MISSED\n"
                        "      needs 1.2x of 101.2x gone (1%); its parts sum to 98.9x, within the target: the 2.3x "
                        "beyond them is the difference between separately timed medians, not a part to remove\n"),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find("takes ,"), std::string::npos) << text;
}

TEST(Bench, TimingRowsAreCompleteAndConsumeResults) {
    std::map<std::string, std::vector<corpus_case>> by_family;
    for (const corpus_case& c : sample_cases()) by_family[c.family].push_back(c);
    timing_options options;
    options.variants = {"naive", "hearn_baker"};
    options.repetitions = 2;
    options.min_time_s = 0.001;
    options.warmup_s = 0;
    const std::vector<timing_row> rows = time_variants(by_family, options);
    // 2 variants × 3 precisions × 4 families, then the filtered oracle and
    // the reference route per family.
    ASSERT_EQ(rows.size(), 2u * 3u * 4u + 2u * 4u);
    std::set<std::string> labels;
    for (const timing_row& r : rows) {
        labels.insert(r.label() + "@" + r.family);
        EXPECT_EQ(r.ns_per_test.size(), 2u) << r.label();
        EXPECT_GT(r.median, 0) << r.label();
        EXPECT_LE(r.min, r.median);
        EXPECT_GE(r.max, r.median);
        EXPECT_GT(r.cases, 0u);
        if (r.precision != "exact" && r.family == "uniform") {
            EXPECT_GT(r.checksum, 0) << r.label();
        }
    }
    EXPECT_EQ(labels.size(), rows.size());
    EXPECT_EQ(rows[rows.size() - 5].variant, "exact_oracle");
    EXPECT_EQ(rows.back().variant, "exact_reference");
    timing_options unknown;
    unknown.variants = {"no_such_variant"};
    EXPECT_THROW(time_variants(by_family, unknown), std::exception);
}

// bench --oracle: every family and "all" timed on every route, the algebraic one included.
TEST(Bench, OracleTimingTimesEveryRoute) {
    oracle_timing_options options;
    options.repetitions = 1;
    options.min_time_s = 0.001;
    const oracle_timing t = time_oracle(sample_cases(), options);
    ASSERT_EQ(t.families.size(), 4u);
    for (const oracle_timing_row& r : t.families) {
        EXPECT_EQ(r.cases, 40u) << r.family;
        EXPECT_GT(r.fast_ns, 0) << r.family;
        EXPECT_GT(r.reference_ns, 0) << r.family;
        EXPECT_GT(r.algebraic_ns, 0) << r.family;
        EXPECT_GT(r.algebraic_over_fast, 0) << r.family;  // one repetition: its own ratio
        EXPECT_EQ(r.algebraic_over_fast, r.algebraic_ns / r.fast_ns) << r.family;
        EXPECT_GT(r.filter_ns, 0) << r.family;
        EXPECT_EQ(r.filter_over_naive, r.filter_ns / r.naive_ns) << r.family;
        EXPECT_GT(r.static_ns, 0) << r.family;
        EXPECT_EQ(r.static_over_naive, r.static_ns / r.naive_ns) << r.family;
        EXPECT_GE(r.static_share, 0) << r.family;
        EXPECT_LE(r.static_share, 1) << r.family;
        EXPECT_GT(r.class_ns, 0) << r.family;
        EXPECT_EQ(r.class_over_naive, r.class_ns / r.naive_ns) << r.family;
        EXPECT_GT(r.roots_ns, 0) << r.family;
        EXPECT_EQ(r.roots_over_naive, r.roots_ns / r.naive_ns) << r.family;
        EXPECT_GT(r.class_per_call_over_naive, 0) << r.family;
        EXPECT_GT(r.roots_per_call_over_naive, 0) << r.family;
    }
    EXPECT_EQ(t.all.cases, 160u);
    const std::string table = format_oracle_timing(t);
    EXPECT_NE(table.find("algebraic_ns"), std::string::npos) << table;
    EXPECT_NE(table.find("alg/oracle"), std::string::npos) << table;
    EXPECT_NE(table.find("filter/naive"), std::string::npos) << table;
    EXPECT_NE(table.find("static/naive"), std::string::npos) << table;
    EXPECT_NE(table.find("class/naive"), std::string::npos) << table;
    EXPECT_NE(table.find("roots/naive"), std::string::npos) << table;
    // The partial answers' targets time a batch, and say what one call per case costs.
    for (const char* family : {"uniform", "far_sphere"})
        for (const char* depth : {"class and signs", "roots rounded"}) {
            const std::size_t at = table.find(fmt::format("oracle {} / naive, {} ", depth, family));
            ASSERT_NE(at, std::string::npos) << depth << ", " << family << "\n" << table;
            EXPECT_NE(table.find("      one call per case: ", at), std::string::npos) << table;
        }
    // Every missed target is followed by what meeting it would take.
    std::istringstream lines(table);
    std::string line, previous;
    while (std::getline(lines, line)) {
        if (previous.find("MISSED") != std::string::npos) {
            EXPECT_EQ(line.rfind("      needs ", 0), 0u) << previous << "\n" << line;
        }
        previous = line;
    }
}

// The median's interval from order statistics, by hand: with 9 repetitions,
// x_(2) and x_(8) cover the median with 1 − 2·(C(9,0) + C(9,1))/2^9 = 0.9609375
// (x_(3), x_(7) would cover 0.8203125, short of 95%); with 5, no pair reaches
// 95%: the minimum and maximum, 1 − 2/32 = 0.9375; with 20, x_(6) and x_(15)
// (1 − 2·P(B(20, ½) ≤ 5) = 0.9586105346679688).
TEST(Bench, MedianIntervalIsTheOrderStatisticsThatCoverIt) {
    const bench::median_interval nine = bench::median_confidence_interval({9, 1, 8, 2, 7, 3, 6, 4, 5});
    EXPECT_EQ(nine.low, 2);
    EXPECT_EQ(nine.high, 8);
    EXPECT_DOUBLE_EQ(nine.confidence, 0.9609375);
    const bench::median_interval five = bench::median_confidence_interval({5, 4, 3, 2, 1});
    EXPECT_EQ(five.low, 1);
    EXPECT_EQ(five.high, 5);
    EXPECT_DOUBLE_EQ(five.confidence, 0.9375);
    std::vector<double> twenty;
    for (int i = 20; i >= 1; --i) twenty.push_back(i);
    const bench::median_interval t = bench::median_confidence_interval(twenty);
    EXPECT_EQ(t.low, 6);
    EXPECT_EQ(t.high, 15);
    EXPECT_NEAR(t.confidence, 0.9586105346679688, 1e-15);
}

TEST(Bench, MedianAndSweep) {
    EXPECT_EQ(median_of({3, 1, 2}), 2);
    EXPECT_EQ(median_of({4, 1, 2, 3}), 2.5);
    EXPECT_EQ(median_of({}), 0);
    EXPECT_EQ(distance_decade(4096), "d/r 1e3..1e4");
    for (const corpus_case& c : far_sphere_sweep(50, 2)) EXPECT_EQ(c.family.rfind("d/r 1e", 0), 0u) << c.id;
}

}  // namespace
}  // namespace rayverify::bench
