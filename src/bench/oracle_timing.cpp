#include "bench/oracle_timing.h"

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <map>

#include "bench/collecting_reporter.h"
#include "bench/timing.h"
#include "compare/audit.h"
#include "intersectors/naive.h"
#include "oracle/algebraic_route.h"
#include "oracle/filter.h"
#include "oracle/oracle.h"
#include "oracle/static_filter.h"

namespace rayverify::bench {
namespace {


// Median CPU ns per case of `body`, which runs one pass over `cases` cases.
double median_ns(const std::string& name, std::size_t cases, const std::function<void()>& body,
                 const oracle_timing_options& options) {
    collecting_reporter reporter;
    benchmark::RegisterBenchmark(name.c_str(),
                                 [&body](benchmark::State& state) {
                                     for (auto _ : state) body();
                                 })
        ->Repetitions(options.repetitions)
        ->MinTime(options.min_time_s)
        ->ReportAggregatesOnly(false);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::ClearRegisteredBenchmarks();
    std::vector<double> ns;
    for (const auto& run : reporter.repetitions)
        ns.push_back(run.cpu_accumulated_time / static_cast<double>(run.iterations) * 1e9 /
                     static_cast<double>(std::max<std::size_t>(cases, 1)));
    return median_of(ns);
}

// The naive intersector inlined into the loop, as timing.cpp times it.
[[gnu::flatten]] void naive_pass(const std::vector<ray_sphere<double>>& inputs) {
    for (const ray_sphere<double>& s : inputs) {
        auto result = intersectors::naive(s);
        benchmark::DoNotOptimize(result);
    }
}

struct prepared {
    std::vector<corpus_case> cases;  // valid in double
    std::vector<ray_sphere<double>> inputs;
};

oracle_timing_row time_family(const std::string& family, const prepared& p, const oracle_timing_options& options,
                              std::size_t& done, std::size_t total, void (*on_progress)(std::size_t, std::size_t)) {
    oracle_timing_row row;
    row.family = family;
    row.cases = p.cases.size();
    const auto tick = [&] {
        if (on_progress) on_progress(++done, total);
    };
    const auto oracle_pass = [&p](exact_solution (*solve)(const ray_sphere<double>&, precision, std::optional<double>,
                                                          std::optional<double>)) {
        return [&p, solve] {
            for (const corpus_case& c : p.cases) {
                exact_solution e = solve(c.geometry, precision::binary64, c.tmin, c.tmax);
                benchmark::DoNotOptimize(e);
            }
        };
    };
    std::vector<exact_roots> answers(p.inputs.size());
    const auto partial_pass = [&p, &answers](oracle_depth depth) {
        return [&p, &answers, depth] {
            solve_exact_roots(p.inputs, precision::binary64, depth, answers);
            benchmark::DoNotOptimize(answers.data());
            benchmark::ClobberMemory();
        };
    };
    const auto partial_per_call_pass = [&p](oracle_depth depth) {
        return [&p, depth] {
            for (const ray_sphere<double>& g : p.inputs) {
                exact_roots e = solve_exact_roots(g, precision::binary64, depth);
                benchmark::DoNotOptimize(e);
            }
        };
    };
    const auto filter_pass = [&p] {
        for (const corpus_case& c : p.cases) {
            oracle_internal::filtered_case f = oracle_internal::filter_case(c.geometry, precision::binary64);
            benchmark::DoNotOptimize(f);
        }
    };
    const auto static_pass = [&p](oracle_depth depth) {
        return [&p, depth] {
            for (const corpus_case& c : p.cases) {
                oracle_internal::filtered_case f;
                const bool settled = oracle_internal::static_filter_case(c.geometry, precision::binary64, f, depth);
                benchmark::DoNotOptimize(settled);
                benchmark::DoNotOptimize(f);
            }
        };
    };
    const auto algebraic_pass = [&p] {
        for (const corpus_case& c : p.cases) {
            algebraic_answer a = solve_algebraic(c.geometry, precision::binary64, c.tmin, c.tmax);
            benchmark::DoNotOptimize(a);
        }
    };
    // One repetition of each benchmark at a time, all of them back to back.
    oracle_timing_options once = options;
    once.repetitions = 1;
    std::vector<double> naive, fast, reference, algebraic, filter, fast_ratio, reference_ratio, algebraic_ratio,
        filter_ratio, static_filter, static_ratio, partial_class, class_ratio, partial_roots, roots_ratio,
        static_class_ratio, class_per_call_ratio, roots_per_call_ratio;
    for (int r = 0; r < options.repetitions; ++r) {
        naive.push_back(time_naive(p.inputs, once, family));
        static_filter.push_back(
            median_ns("static_filter_case/" + family, row.cases, static_pass(oracle_depth::roots_rounded), once));
        static_ratio.push_back(static_filter.back() / naive.back());
        filter.push_back(median_ns("filter_case/" + family, row.cases, filter_pass, once));
        filter_ratio.push_back(filter.back() / naive.back());
        partial_class.push_back(median_ns("solve_exact_roots/class_and_signs/" + family, row.cases,
                                          partial_pass(oracle_depth::class_and_signs), once));
        class_ratio.push_back(partial_class.back() / naive.back());
        static_class_ratio.push_back(median_ns("static_filter_case/class_and_signs/" + family, row.cases,
                                               static_pass(oracle_depth::class_and_signs), once) /
                                     naive.back());
        partial_roots.push_back(median_ns("solve_exact_roots/roots_rounded/" + family, row.cases,
                                          partial_pass(oracle_depth::roots_rounded), once));
        roots_ratio.push_back(partial_roots.back() / naive.back());
        class_per_call_ratio.push_back(median_ns("solve_exact_roots/class_and_signs/per_call/" + family, row.cases,
                                                 partial_per_call_pass(oracle_depth::class_and_signs), once) /
                                       naive.back());
        roots_per_call_ratio.push_back(median_ns("solve_exact_roots/roots_rounded/per_call/" + family, row.cases,
                                                 partial_per_call_pass(oracle_depth::roots_rounded), once) /
                                       naive.back());
        fast.push_back(median_ns("solve_exact/" + family, row.cases, oracle_pass(&solve_exact), once));
        reference.push_back(
            median_ns("solve_exact_reference/" + family, row.cases, oracle_pass(&solve_exact_reference), once));
        algebraic.push_back(median_ns("solve_algebraic/" + family, row.cases, algebraic_pass, once));
        fast_ratio.push_back(fast.back() / naive.back());
        reference_ratio.push_back(reference.back() / fast.back());
        algebraic_ratio.push_back(algebraic.back() / fast.back());
    }
    row.naive_ns = median_of(naive);
    row.fast_ns = median_of(fast);
    row.reference_ns = median_of(reference);
    row.algebraic_ns = median_of(algebraic);
    row.fast_over_naive = median_of(fast_ratio);
    row.reference_over_fast = median_of(reference_ratio);
    row.algebraic_over_fast = median_of(algebraic_ratio);
    row.filter_ns = median_of(filter);
    row.filter_over_naive = median_of(filter_ratio);
    row.class_ns = median_of(partial_class);
    row.class_over_naive = median_of(class_ratio);
    row.roots_ns = median_of(partial_roots);
    row.roots_over_naive = median_of(roots_ratio);
    row.class_per_call_over_naive = median_of(class_per_call_ratio);
    row.roots_per_call_over_naive = median_of(roots_per_call_ratio);
    row.static_class_over_naive = median_of(static_class_ratio);
    row.static_ns = median_of(static_filter);
    row.static_over_naive = median_of(static_ratio);
    std::size_t settled = 0;
    for (const corpus_case& c : p.cases) {
        oracle_internal::filtered_case f;
        settled += oracle_internal::static_filter_case(c.geometry, precision::binary64, f, oracle_depth::roots_rounded);
    }
    row.static_share = row.cases ? double(settled) / double(row.cases) : 0;
    for (int k = 0; k < 4; ++k) tick();

    // Fallback rates, double inputs and float inputs (as the audit solves them).
    std::size_t exact_double = 0, valid_float = 0, exact_float = 0;
    for (const corpus_case& c : p.cases) {
        exact_double += solve_exact(c.geometry, precision::binary64, c.tmin, c.tmax).stage == oracle_stage::exact;
        if (validity<float>(c.geometry) != invalid_reason::none) continue;
        const auto narrow = [](std::optional<double> t) -> std::optional<double> {
            if (!t) return t;
            return double(float(*t));
        };
        const exact_solution f = solve_exact(rounded_to<double>(rounded_to<float>(c.geometry)), precision::binary32,
                                             narrow(c.tmin), narrow(c.tmax));
        if (!f.valid()) continue;
        ++valid_float;
        exact_float += f.stage == oracle_stage::exact;
    }
    row.fallback_double = row.cases ? double(exact_double) / double(row.cases) : 0;
    row.fallback_float = valid_float ? double(exact_float) / double(valid_float) : 0;
    return row;
}

}  // namespace

double time_naive(const std::vector<ray_sphere<double>>& inputs, const oracle_timing_options& options,
                  const std::string& label) {
    return median_ns("naive/" + label, inputs.size(), [&inputs] { naive_pass(inputs); }, options);
}

oracle_timing time_oracle(const std::vector<corpus_case>& cases, const oracle_timing_options& options,
                          void (*on_progress)(std::size_t, std::size_t)) {
    std::map<std::string, prepared> by_family;
    prepared all;
    for (const corpus_case& c : cases) {
        if (validity<double>(c.geometry) != invalid_reason::none) continue;
        for (prepared* p : {&by_family[family_key(c)], &all}) {
            p->cases.push_back(c);
            p->inputs.push_back(c.geometry);
        }
    }
    oracle_timing out;
    out.repetitions = options.repetitions;
    std::size_t done = 0;
    const std::size_t total = 4 * (by_family.size() + 1);
    for (const auto& [family, p] : by_family)
        out.families.push_back(time_family(family, p, options, done, total, on_progress));
    out.all = time_family("all", all, options, done, total, on_progress);
    return out;
}

std::string format_oracle_timing(const oracle_timing& t) {
    std::string out =
        fmt::format("{:<20} {:>6} {:>9} {:>10} {:>13} {:>13} {:>12} {:>12} {:>12} {:>10} {:>10} {:>13} {:>8} {:>13} "
                    "{:>10} {:>9}\n",
                    "family", "cases", "naive_ns", "oracle_ns", "reference_ns", "algebraic_ns", "class/naive",
                    "roots/naive", "oracle/naive", "ref/oracle", "alg/oracle", "static/naive", "static",
                    "filter/naive", "fallback64", "fallback32");
    const auto line = [&out](const oracle_timing_row& r) {
        out += fmt::format("{:<20} {:>6} {:>9.2f} {:>10.1f} {:>13.1f} {:>13.1f} {:>11.1f}x {:>11.1f}x {:>11.1f}x "
                           "{:>9.1f}x {:>9.1f}x {:>12.1f}x {:>7.1f}% {:>12.1f}x {:>9.2f}% {:>8.2f}%\n",
                           r.family, r.cases, r.naive_ns, r.fast_ns, r.reference_ns, r.algebraic_ns,
                           r.class_over_naive, r.roots_over_naive, r.fast_over_naive,
                           r.reference_over_fast, r.algebraic_over_fast, r.static_over_naive, 100 * r.static_share,
                           r.filter_over_naive, 100 * r.fallback_double, 100 * r.fallback_float);
    };
    for (const oracle_timing_row& r : t.families) line(r);
    line(t.all);
    out += fmt::format("ns per case, CPU time, median of {} repetitions (ratios: medians of each repetition's, the "
                       "benchmarks timed back to back); class = solve_exact_roots answering the class and the roots' "
                       "signs alone, roots = the same with both roots correctly rounded (oracle_depth; no interval, "
                       "no hit point, no state kept), each asked for the family's cases as one batch; oracle = solve_exact (filtered): a whole solution, the class, signs, rounded roots "
                       "and the enclosures later questions start from (hit points are rounded when asked), reference = "
                       "solve_exact_reference, algebraic = solve_algebraic (CGAL::Sqrt_extension), all on the double "
                       "inputs with the case's interval; static = the static filter alone as solve_exact runs it "
                       "(oracle_internal::static_filter_case to the rounded roots: the first stage of solve_exact, "
                       "plain double with a-priori bounds, no interval) and the share of cases it settles; filter = the double-word "
                       "filter alone (oracle_internal::filter_case: the second stage, for the cases the static one "
                       "leaves); fallback = share of solutions that needed exact arithmetic (double inputs, float "
                       "inputs).\n",
                       t.repetitions);
    out += "targets, this run:\n";
    const auto target = [&out](const std::string& what, double value, double limit, bool at_most) {
        const bool met = target_met(value, limit, at_most ? target_direction::at_most : target_direction::at_least);
        out += fmt::format("  {:<44} {:>8.1f}x  target {}{:g}x  {}\n", what, value, at_most ? "<= " : ">= ", limit,
                           met ? "met" : "MISSED");
        return met;
    };
    // The partial answers, on the ordinary families: what the class and signs
    // cost, and what rounding both roots adds, asked for the family's cases as
    // one batch; and what asking case by case adds (the environment's check,
    // and for the roots the misses taken among the hits).
    constexpr double class_limit = 5.0, roots_limit = 10.0;
    const auto per_call = [&out](double batch, double each, std::string_view batch_also) {
        out += fmt::format("      one call per case: {:.1f}x ({:+.1f}x: each call checks the IEEE environment, "
                           "reading MXCSR, which waits for the operations in flight; a batch checks it once{})\n",
                           each, each - batch, batch_also);
    };
    for (const oracle_timing_row& r : t.families) {
        if (r.family != "uniform" && r.family != "far_sphere") continue;
        if (!target(fmt::format("oracle class and signs / naive, {}", r.family), r.class_over_naive, class_limit, true))
            out += fmt::format("      needs {:.1f}x of {:.1f}x gone ({:.0f}%); the static filter stopped after the "
                               "class and signs takes {:.1f}x (the range check, a, b', C and b'² - aC in plain double "
                               "with their a-priori bounds, Lagrange's Δ' only where b'² - aC cancels; no root, "
                               "square root or division, where naive computes a, b', C and b'² - aC unbounded, "
                               "√Δ' and a root), the rest {:.1f}x (the stage count, the result): meeting it needs {}\n",
                               r.class_over_naive - class_limit, r.class_over_naive,
                               100 * (r.class_over_naive - class_limit) / r.class_over_naive,
                               r.static_class_over_naive, r.class_over_naive - r.static_class_over_naive,
                               r.static_class_over_naive > class_limit
                                   ? "fewer operations than the coefficients naive computes and their bounds: "
                                     "several cases at once (vectorised), not one case faster"
                                   : "less around the filter: the stage counted once per batch, the result written "
                                     "in fewer bytes");
        per_call(r.class_over_naive, r.class_per_call_over_naive, "");
        if (!target(fmt::format("oracle roots rounded / naive, {}", r.family), r.roots_over_naive, roots_limit, true))
            out += fmt::format("      needs {:.1f}x of {:.1f}x gone ({:.0f}%); the class and signs take {:.1f}x, "
                               "rounding both roots {:.1f}x more (the class again, then their residuals from "
                               "error-free products and one Newton step, both roots at once, and the roundings of "
                               "their enclosures; misses answered first): meeting it needs a root rounded from one "
                               "correction cheaper than that step, or only the root a question asks for\n",
                               r.roots_over_naive - roots_limit, r.roots_over_naive,
                               100 * (r.roots_over_naive - roots_limit) / r.roots_over_naive, r.class_over_naive,
                               r.roots_over_naive - r.class_over_naive);
        per_call(r.roots_over_naive, r.roots_per_call_over_naive,
                 ", and answers the misses among each 64 cases before it rounds the others' roots, where one by one "
                 "a miss or a hit comes as it may and the branch between them mispredicts");
    }
    for (const oracle_timing_row& r : t.families) {
        const bool ordinary = r.family == "uniform" || r.family == "far_sphere";
        const double limit = ordinary ? 10.0 : 100.0;
        if (target(fmt::format("oracle everything / naive, {}", r.family), r.fast_over_naive, limit, true)) continue;
        out += fmt::format("      needs {:.1f}x of {:.1f}x gone ({:.0f}%); ", r.fast_over_naive - limit,
                           r.fast_over_naive, 100 * (r.fast_over_naive - limit) / r.fast_over_naive);
        if (r.static_share >= 0.5 && r.static_over_naive > limit)
            // Most cases end in the static filter, and it alone exceeds the target.
            out += fmt::format("the static filter alone takes {:.1f}x and settles {:.0f}% of cases; the rest of "
                               "solve_exact (the solution's bookkeeping, the double-word filter for the cases left) "
                               "{:.1f}x: meeting it needs a certified answer cheaper than two Newton-corrected "
                               "roots, not a faster solve_exact\n",
                               r.static_over_naive, 100 * r.static_share, r.fast_over_naive - r.static_over_naive);
        else if (r.static_share >= 0.5)
            out += fmt::format("the static filter takes {:.1f}x and settles {:.0f}% of cases; the rest of "
                               "solve_exact (the solution's bookkeeping, the double-word filter for the cases left) "
                               "{:.1f}x: that must fall to {:.1f}x\n",
                               r.static_over_naive, 100 * r.static_share, r.fast_over_naive - r.static_over_naive,
                               limit - r.static_over_naive);
        else {
            // Most cases pass through both filters and the stages after them.
            const double beyond = r.fast_over_naive - r.static_over_naive - r.filter_over_naive;
            out += fmt::format("the static filter settles {:.0f}% of cases and takes {:.1f}x, the double-word filter "
                               "{:.1f}x, the stages after them (expansions, refinements, exact fallbacks: {:.1f}% and "
                               "{:.1f}% of solutions needed GMP) {:.1f}x: these must fall to {:.1f}x\n",
                               100 * r.static_share, r.static_over_naive, r.filter_over_naive,
                               100 * r.fallback_double, 100 * r.fallback_float, beyond,
                               limit - r.static_over_naive - r.filter_over_naive);
        }
    }
    constexpr double reference_limit = 50.0;
    if (!target("reference / oracle, whole corpus", t.all.reference_over_fast, reference_limit, false)) {
        // The filtered oracle's time over the corpus by family, largest first.
        std::vector<std::pair<double, const oracle_timing_row*>> spent;
        double total = 0;
        for (const oracle_timing_row& r : t.families) {
            spent.emplace_back(r.fast_ns * static_cast<double>(r.cases), &r);
            total += spent.back().first;
        }
        std::sort(spent.begin(), spent.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        out += fmt::format("      needs the filtered oracle at {:.0f} ns per case or less (reference {:.0f} / {:g}), "
                           "not {:.0f} ({:.0f}% less); its time by family:",
                           t.all.reference_ns / reference_limit, t.all.reference_ns, reference_limit, t.all.fast_ns,
                           100 * (1 - t.all.reference_ns / reference_limit / t.all.fast_ns));
        for (const auto& [ns, r] : spent)
            out += fmt::format(" {} {:.0f}% (ref/oracle {:.1f}x)", r->family, total > 0 ? 100 * ns / total : 0.0,
                               r->reference_over_fast);
        out += '\n';
    }
    return out;
}

}  // namespace rayverify::bench
