// Run time of the exact oracle: the fast (filtered) oracle against the naive
// double intersector, the reference oracle and the algebraic route
// (oracle/algebraic_route.h), measured in one run
// with Google Benchmark, and the filter's fallback rate per family (the share
// of solutions that needed exact arithmetic: a measure of how stiff a family
// is). Measuring only; format_oracle_timing renders the figures as text.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/ray_sphere_case.h"

namespace rayverify::bench {

struct oracle_timing_options {
    int repetitions = 5;
    double min_time_s = 0.05;  // per repetition
};

// One family (or "all": the whole corpus given), double precision unless noted.
struct oracle_timing_row {
    std::string family;
    std::size_t cases = 0;
    double naive_ns = 0;      // naive intersector, double, per case
    double fast_ns = 0;       // solve_exact (double inputs, the case's interval): everything
    // Partial answers (solve_exact_roots, no interval): the class and the
    // roots' signs, and those with both roots correctly rounded; each with its
    // ratio to naive (median of each repetition's). Asked for the family's
    // cases as one batch (the environment checked once), and case by case
    // (checked on every call).
    double class_ns = 0, class_over_naive = 0;
    double roots_ns = 0, roots_over_naive = 0;
    double class_per_call_over_naive = 0, roots_per_call_over_naive = 0;
    // The static filter alone stopped after the class and signs (its ratio to
    // naive): what of class_ns is the filter's arithmetic, and what the rest
    // (the stage count, the result written; the environment's check is the
    // per-call figure's, once per batch in class_ns).
    double static_class_over_naive = 0;
    double reference_ns = 0;  // solve_exact_reference, same inputs
    double algebraic_ns = 0;  // solve_algebraic, same inputs
    // The static filter alone as solve_exact runs it (oracle_internal::
    // static_filter_case to the rounded roots: plain double with a-priori
    // bounds, one Newton step per root; the first stage of solve_exact), its ratio to naive (median of each repetition's) and
    // the share of cases it settles: the least a certified answer of this
    // design costs, and how often that is all it costs.
    double static_ns = 0, static_over_naive = 0, static_share = 0;
    // The double-word filter alone (oracle_internal::filter_case: Δ′'s sign,
    // the roots' enclosures, signs and roundings, the hit point), which runs
    // where the static filter cannot settle a case, and its ratio to naive.
    double filter_ns = 0, filter_over_naive = 0;
    // Share of valid solutions with stage == exact, double and float inputs.
    double fallback_double = 0, fallback_float = 0;
    // Medians of each repetition's ratio of neighbouring timings (every
    // repetition times the six back to back; a shared machine's speed drifts
    // between repetitions, not within one).
    double fast_over_naive = 0, reference_over_fast = 0, algebraic_over_fast = 0;
};

struct oracle_timing {
    std::vector<oracle_timing_row> families;  // every family in the corpus, by name
    oracle_timing_row all;                    // the whole corpus
    int repetitions = 0;
};

// Times every family of `cases` and the whole set (medians of CPU time over
// the repetitions, and of the repetitions' ratios). `on_progress(done, total)`
// after each benchmark.
oracle_timing time_oracle(const std::vector<corpus_case>& cases, const oracle_timing_options& options,
                          void (*on_progress)(std::size_t, std::size_t) = nullptr);

// Median CPU ns per case of the naive double intersector over `inputs`,
// inlined into the loop: the reference every ratio of bench --oracle and
// bench --audit is taken against.
double time_naive(const std::vector<ray_sphere<double>>& inputs, const oracle_timing_options& options,
                  const std::string& label);

// The figures as a table, with the targets (on uniform and far_sphere: the
// class and signs ≤ 5× naive, the roots rounded ≤ 10×, everything ≤ 10×;
// everything ≤ 100× on every other family; reference ≥ 50× fast on the whole
// corpus), whether this run met them, and for a missed one how far off it is
// and what meeting it would take, from this run's figures.
std::string format_oracle_timing(const oracle_timing& t);

}  // namespace rayverify::bench
