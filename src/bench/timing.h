// Run time of the intersectors and of the exact oracle, measured with Google
// Benchmark. Measuring only: reports render what this returns.
//
// Each (variant, precision, family) is one benchmark whose body is a tight
// loop over that family's cases, pre-rounded to the precision, calling the
// intersector through a template instantiated on its concrete function (see
// kernels.h), each result passed to benchmark::DoNotOptimize. Google
// Benchmark warms up, picks the iteration count so that one repetition lasts
// at least `min_time_s`, and repeats; we keep every repetition's CPU time.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/ray_sphere_case.h"
#include "intersectors/registry.h"

namespace rayverify::bench {

struct timing_options {
    std::vector<std::string> variants;  // empty: all built-in variants (unless builtins is false)
    bool builtins = true;               // false: time only the plugins
    // Variants without an inlined kernel (plugins): timed in float and double
    // through their function, a call through a pointer per test. The engine
    // ports among the built-in variants (variant::build) are timed the same way.
    std::vector<variant> plugins;
    // The precisions timed, of timed_precisions; empty: all of them.
    std::vector<std::string> precisions;
    int repetitions = 9;
    double min_time_s = 0.01;     // per repetition
    double warmup_s = 0.02;       // before the first repetition
    bool include_oracle = true;   // also time solve_exact and solve_exact_reference (double inputs)
};

// Whether a measured figure meets its target: at most `limit` (a cost) or at
// least `limit` (a speed-up). The one test behind every benchmark's met /
// MISSED. For tests only, RAYVERIFY_TEST_BENCH_TARGETS=met (or =missed)
// makes every target met (or missed) whatever was measured, so that a
// documented benchmark block can be checked against both branches on any
// machine (docs/testing.md); any other value is ignored.
enum class target_direction { at_most, at_least };
bool target_met(double value, double limit, target_direction direction);

// Precisions timed: the two the audit judges plus long double.
inline constexpr const char* timed_precisions[] = {"float", "double", "long double"};

// Whether `options` time precision `prec` (one of timed_precisions).
inline bool times_precision(const timing_options& options, std::string_view prec) {
    return options.precisions.empty() ||
           std::find(options.precisions.begin(), options.precisions.end(), prec) != options.precisions.end();
}

// Whether `options` time the built-in variant `name`.
inline bool times_builtin(const timing_options& options, std::string_view name) {
    return options.builtins && (options.variants.empty() || std::find(options.variants.begin(),
                                                                      options.variants.end(), name) !=
                                                                options.variants.end());
}

struct timing_row {
    std::string variant;    // a registry or plugin name, "exact_oracle" or "exact_reference"
    std::string precision;  // "float", "double", "long double"; "exact" for the oracle
    std::string family;
    std::size_t cases = 0;  // cases in one pass (valid at that precision)
    // ns per ray–sphere test, CPU time, one value per repetition, in run order.
    std::vector<double> ns_per_test;
    std::vector<double> real_ns_per_test;  // wall-clock time, same repetitions
    std::vector<std::uint64_t> tests;      // ray–sphere tests timed, same repetitions
    double median = 0, min = 0, max = 0;   // of ns_per_test
    double real_median = 0;
    double checksum = 0;  // sum of returned counts over one pass: proves the results were used
    std::string label() const { return variant + "/" + precision; }
};

// Times every selected variant in every precision on each family's cases
// (families in map order), then the oracle if asked. `on_progress(done,
// total)` is called after each benchmark. Throws input_error for an unknown
// variant name.
std::vector<timing_row> time_variants(const std::map<std::string, std::vector<corpus_case>>& cases_by_family,
                                      const timing_options& options,
                                      void (*on_progress)(std::size_t, std::size_t) = nullptr);

// Time one pass of a caller's loop like a row of time_variants: `one_pass`
// runs the loop once over `row.cases` items and returns a value that depends
// on every result (so nothing is optimised away). Fills ns_per_test (per
// item), the medians, min, max and the checksum (one pass's value).
timing_row time_pass(timing_row row, const std::function<double()>& one_pass, const timing_options& options);

// Median of a sample (mean of the two middle values for an even count); 0 for empty.
double median_of(std::vector<double> values);

// A distribution-free confidence interval for the median of the distribution
// the repetitions are drawn from (independent, identically distributed): the
// order statistics x_(k) and x_(n+1−k) with the largest k whose coverage
// 1 − 2·P(Binomial(n, 1/2) ≤ k − 1) is at least `wanted`; with too few
// repetitions for that (n < 6 at 0.95), the minimum and maximum with the
// coverage they have. `confidence` is the coverage of the interval given.
struct median_interval {
    double low = 0, high = 0, confidence = 0;
};
inline median_interval median_confidence_interval(std::vector<double> values, double wanted = 0.95) {
    median_interval out;
    if (values.empty()) return out;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    // below[k] = P(Binomial(n, 1/2) <= k), summed in doubles: n is a repetition count.
    std::vector<double> below(n + 1);
    double term = std::ldexp(1.0, -static_cast<int>(n)), sum = 0;  // C(n, 0) / 2^n
    for (std::size_t k = 0; k <= n; ++k) {
        sum += term;
        below[k] = sum;
        term = term * static_cast<double>(n - k) / static_cast<double>(k + 1);
    }
    std::size_t chosen = 1;
    out.confidence = 1 - 2 * below[0];
    for (std::size_t k = 2; 2 * k <= n + 1; ++k) {
        const double coverage = 1 - 2 * below[k - 1];
        if (coverage < wanted) break;
        chosen = k;
        out.confidence = coverage;
    }
    out.low = values[chosen - 1];
    out.high = values[n - chosen];
    return out;
}

// The CPU model from /proc/cpuinfo ("unknown" when unreadable).
std::string cpu_model();

// The machine a run's timings were taken on, as far as Linux shows it to an
// unprivileged process: the CPU's model and feature flags (/proc/cpuinfo), its
// clock (the current and the maximum MHz, where /proc/cpuinfo or cpufreq gives
// them; a VM often shows neither truthfully), the load average when read
// (/proc/loadavg: other work on the machine while timing), the kernel
// (uname) and the hardware threads. Absent values stay empty.
struct machine_record {
    std::string cpu;
    std::vector<std::string> cpu_flags;
    std::optional<double> cpu_mhz, cpu_max_mhz;
    std::optional<std::array<double, 3>> load_average;  // 1, 5 and 15 minutes
    std::string kernel;
    unsigned hardware_threads = 0;
};
machine_record read_machine_record();

}  // namespace rayverify::bench
