#include "cli/bench_audit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <ctime>
#include <map>
#include <streambuf>

#include "bench/oracle_timing.h"
#include "bench/timing.h"
#include "cli/commands.h"
#include "corpus/case_stream.h"
#include "corpus/manifest.h"
#include "oracle/oracle.h"
#include "report/audit_pass.h"
#include "report/audit_report.h"

namespace rayverify::cli {
namespace {

// The targets the per case-target ratio is measured with: the 13 built-in
// variants of before the engine ports, in both precisions (26 targets), so
// that adding variants does not move the figure (docs/oracle.md).
const std::vector<std::string> ratio_variants = {
    "naive",         "half_b",          "seed003_reduced",     "seed004_early_out",  "geometric",
    "stable_roots",  "hearn_baker",     "fma_discriminant",    "hearn_baker_any_hit", "hearn_baker_nearest",
    "hearn_baker_unit", "hearn_baker_unit_nearest", "hearn_baker_unit_any_hit"};

// An output stream that takes every character and keeps none: the per-case
// lines are rendered and written as the audit writes them, to no file.
class discarding_buffer : public std::streambuf {
public:
    std::uint64_t bytes = 0;  // taken so far

protected:
    int_type overflow(int_type c) override {
        ++bytes;
        return traits_type::not_eof(c);
    }
    std::streamsize xsputn(const char*, std::streamsize n) override {
        bytes += static_cast<std::uint64_t>(n);
        return n;
    }
};

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// Where a whole audit's time goes, per case-target in multiples of naive
// double's time per case. The targets' answers and the oracle are timed on
// their own; the other three are differences of neighbouring timings of ever
// larger parts of the pass (audit_case, audit_stream, run_audit_pass), so on a
// noisy machine a small part may come out a little below 0.
struct audit_parts {
    double targets = 0;     // every target's own answers (answer_of on run_input's inputs)
    double oracle = 0;      // solve_case on the double and the float inputs
    double judge = 0;       // audit_case less the two above: outputs widened, ULP errors, verdicts
    double accumulate = 0;  // audit_stream less audit_case: verdict tallies, error histograms
    double stability = 0;   // the whole pass less audit_stream: stability figures, plot sample
    double sum() const { return targets + oracle + judge + accumulate + stability; }
};

// The parts in the order they are printed, with their names.
std::vector<std::pair<std::string, double>> named_parts(const audit_parts& p) {
    return {{"targets", p.targets},
            {"oracle", p.oracle},
            {"judge", p.judge},
            {"accumulate", p.accumulate},
            {"stability", p.stability}};
}

// Every target's own answer on every case it runs on, as audit_case asks for it.
class target_answers {
public:
    target_answers(const std::vector<corpus_case>& cases, const std::vector<audit_target>& targets)
        : cases_(cases), targets_(targets) {
        for (std::size_t t = 0; t < targets.size(); ++t)
            for (std::size_t i = 0; i < cases.size(); ++i) {
                if (targets[t].prec == precision::binary32) {
                    if (auto in = run_input<float>(targets[t], cases[i])) float_runs_.push_back({t, i, *in});
                } else if (auto in = run_input<double>(targets[t], cases[i])) {
                    double_runs_.push_back({t, i, *in});
                }
            }
    }
    // The number of roots answered: depends on every answer.
    double run() const { return run_all(float_runs_) + run_all(double_runs_); }

private:
    template <class T>
    struct run_of {
        std::size_t target, at;
        batch_case<T> input;
    };
    template <class T>
    double run_all(const std::vector<run_of<T>>& runs) const {
        double roots = 0;
        for (const run_of<T>& r : runs)
            roots += answer_of(targets_[r.target], cases_[r.at], r.input.input, r.input.interval).roots.count;
        return roots;
    }
    const std::vector<corpus_case>& cases_;
    const std::vector<audit_target>& targets_;
    std::vector<run_of<float>> float_runs_;
    std::vector<run_of<double>> double_runs_;
};

// `cases` in chunks as the audit reads a corpus, each case's index its place.
case_source chunks_of(const std::vector<corpus_case>& cases) {
    return [&cases, at = std::size_t{0}](std::vector<corpus_case>& chunk, std::vector<std::size_t>& indices) mutable {
        chunk.clear();
        indices.clear();
        for (; at < cases.size() && chunk.size() < case_stream::default_chunk; ++at) {
            chunk.push_back(cases[at]);
            indices.push_back(at);
        }
        return !chunk.empty();
    };
}

struct audit_timing_row {
    std::string family;
    std::size_t cases = 0;
    double naive_ns = 0;     // per case, median over the repetitions
    double audit_ns = 0;     // per case-target, the audit as `rayverify audit --report` runs it, median
    double audit_ratio = 0;  // audit_ns / naive_ns, median of the repetitions' ratios
    double per_case_ratio = 0;  // the audit writing --per-case lines over the audit alone, median of ratios
    double per_case_bytes = 0;  // bytes of per-case lines per case-target
    audit_parts parts;          // where the audit's time goes, × naive, medians of each repetition's ratios
    oracle_stage_counts counts;
    double checksum = 0;  // sums figures of every timed result: proves the results were used
};

audit_timing_row time_family(const std::string& family, const std::vector<corpus_case>& cases,
                             const std::vector<audit_target>& targets, int repetitions, double min_time_s) {
    audit_timing_row row;
    row.family = family;
    row.cases = cases.size();
    std::vector<ray_sphere<double>> inputs;
    for (const corpus_case& c : cases)
        if (validity<double>(c.geometry) == invalid_reason::none) inputs.push_back(c.geometry);

    const auto pass = [&](std::ostream* per_case) {
        return run_audit_pass(chunks_of(cases), targets, 1, true, per_case).audit.cases;
    };
    // CPU ns per case-target of as many runs of `body` (over every case) as
    // fill min_time_s. A body returns a figure that depends on every result
    // it computed, summed into the row's checksum (so nothing is optimised away).
    const double case_targets = static_cast<double>(cases.size() * targets.size());
    const auto ns_per_case_target = [&](const auto& body) {
        const double start = cpu_seconds();
        int passes = 0;
        do {
            row.checksum += body();
            ++passes;
        } while (cpu_seconds() - start < min_time_s);
        return (cpu_seconds() - start) * 1e9 / (passes * case_targets);
    };
    const auto audit_ns = [&](std::ostream* per_case) {
        return ns_per_case_target([&] { return static_cast<double>(pass(per_case)); });
    };

    // The parts, each a larger piece of the pass than the one before.
    const target_answers answers(cases, targets);
    const auto oracle_only = [&] {
        double classes = 0;
        for (const corpus_case& c : cases)
            classes += static_cast<double>(solve_case(c, precision::binary64).cls) +
                       static_cast<double>(solve_case(c, precision::binary32).cls);
        return classes;
    };
    const auto cases_judged = [&] {
        double agreed = 0;
        audited_case judged;
        for (const corpus_case& c : cases) {
            judged = audit_case(c, targets);
            for (const target_outcome& o : judged.outcomes) agreed += o.score.verdict == verdict_kind::agree;
        }
        return agreed;
    };
    const auto stream_only = [&] { return static_cast<double>(audit_stream(chunks_of(cases), targets, 1, {}).cases); };
    // Each repetition times naive, the audit and the audit with per-case
    // lines back to back, and the figures are medians of each repetition's
    // ratios: on a shared machine whose speed drifts, a ratio of neighbours
    // holds where a ratio of medians taken minutes apart does not.
    discarding_buffer discarded;
    std::ostream discard(&discarded);
    std::vector<double> naive, audit, ratio, per_case_ratio;
    std::array<std::vector<double>, 5> parts;  // as named_parts orders them
    for (int r = 0; r < repetitions; ++r) {
        naive.push_back(bench::time_naive(inputs, {1, std::max(min_time_s, 0.05)}, family));
        audit.push_back(audit_ns(nullptr));
        ratio.push_back(audit.back() / naive.back());
        per_case_ratio.push_back(audit_ns(&discard) / audit.back());
        const double answered = ns_per_case_target([&] { return answers.run(); });
        const double solved = ns_per_case_target(oracle_only);
        const double judged = ns_per_case_target(cases_judged);
        const double streamed = ns_per_case_target(stream_only);
        const double whole = audit_ns(nullptr);
        const double in_naive[] = {answered, solved, judged - answered - solved, streamed - judged, whole - streamed};
        for (std::size_t k = 0; k < parts.size(); ++k) parts[k].push_back(in_naive[k] / naive.back());
    }
    row.naive_ns = bench::median_of(naive);
    row.audit_ns = bench::median_of(audit);
    row.audit_ratio = bench::median_of(ratio);
    row.per_case_ratio = bench::median_of(per_case_ratio);
    discarded.bytes = 0;
    pass(&discard);
    row.per_case_bytes = static_cast<double>(discarded.bytes) / case_targets;
    double* const fields[] = {&row.parts.targets, &row.parts.oracle, &row.parts.judge, &row.parts.accumulate,
                              &row.parts.stability};
    for (std::size_t k = 0; k < parts.size(); ++k) *fields[k] = bench::median_of(parts[k]);

    // How the oracle settled the figures: one more pass, counted.
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    counts = {};
    pass(nullptr);
    row.counts = counts;
    return row;
}

double share(std::uint64_t part, std::uint64_t whole) { return whole ? 100.0 * double(part) / double(whole) : 0; }

std::string format_rows(const std::vector<audit_timing_row>& rows, std::size_t target_count, int repetitions) {
    std::string out = fmt::format("{:<15} {:>5} {:>8} {:>11} {:>11} {:>8}", "family", "cases", "naive_ns", "audit_ns/ct",
                                  "audit/naive", "per-case");
    for (const char* kind : {"solve", "ulp", "cmp", "round"})
        out += fmt::format(" {:>9} {:>8}", fmt::format("{}_exp", kind), fmt::format("{}_ex", kind));
    out += '\n';
    for (const audit_timing_row& r : rows) {
        const oracle_stage_counts& c = r.counts;
        out += fmt::format("{:<15} {:>5} {:>8.2f} {:>11.1f} {:>10.1f}x {:>7.2f}x", r.family, r.cases, r.naive_ns,
                           r.audit_ns, r.audit_ratio, r.per_case_ratio);
        for (const stage_tally* t : {&c.solutions, &c.ulp_errors, &c.comparisons, &c.roundings})
            out += fmt::format(" {:>8.2f}% {:>7.2f}%", share(t->expansion, t->total()), share(t->exact, t->total()));
        out += '\n';
    }
    out += fmt::format(
        "audit_ns/ct = CPU ns per case-target of the audit as `rayverify audit --report` runs it (oracle, {} "
        "targets: the 13 textbook variants in float and double, judge, stability, plot sample), one thread, median "
        "of {} repetitions; audit/naive and per-case (the audit writing --per-case lines, over the audit alone) are "
        "medians of each repetition's ratio of neighbouring timings; *_exp, *_ex = share "
        "of the oracle's answers of each kind (solutions of float and double inputs, ULP errors of roots and "
        "hit-point coordinates, comparisons with a value, rounded hit coordinates) that needed floating-point "
        "expansions (no big numbers) or exact arithmetic (GMP); the rest the filters (static, then double-word) settled.\n",
        target_count, repetitions);
    return out;
}

// Where each family's audit time goes: the parts in multiples of naive.
std::string format_parts(const std::vector<audit_timing_row>& rows) {
    std::string out = "where the audit's time goes, x naive double per case-target (medians of each repetition's ratios):\n";
    out += fmt::format("{:<15}", "family");
    for (const auto& [name, value] : named_parts(rows.front().parts)) out += fmt::format(" {:>11}", name);
    out += fmt::format(" {:>11} {:>11}\n", "sum", "audit");
    for (const audit_timing_row& r : rows) {
        out += fmt::format("{:<15}", r.family);
        for (const auto& [name, value] : named_parts(r.parts)) out += fmt::format(" {:>10.1f}x", value);
        out += fmt::format(" {:>10.1f}x {:>10.1f}x\n", r.parts.sum(), r.audit_ratio);
    }
    out += "targets = the 26 targets' own answers; oracle = solve_case on the double and the float inputs; judge = "
           "audit_case less those two (outputs widened, ULP errors, verdicts); accumulate = audit_stream less "
           "audit_case (tallies, error histograms); stability = the whole pass less audit_stream (stability figures, "
           "plot sample). The last three are differences of timings, so noise can leave one a little below 0.\n";
    return out;
}

// For a target the audit missed: how far off it is and what meeting it would
// take, from this run's parts: the share of the time that must go, and the
// largest parts that would have to go entirely for the rest to meet it.
std::string what_it_would_take(const audit_parts& parts, double ratio, double limit) {
    std::vector<std::pair<std::string, double>> largest = named_parts(parts);
    std::sort(largest.begin(), largest.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::string out = fmt::format("      needs {:.1f}x of {:.1f}x gone ({:.0f}%)", ratio - limit, ratio,
                                  100 * (ratio - limit) / ratio);
    double left = parts.sum();
    std::string removed;
    for (const auto& [name, value] : largest) {
        if (left <= limit) break;
        left -= value;
        removed += (removed.empty() ? "" : " + ") + fmt::format("{} ({:.1f}x)", name, value);
    }
    if (left <= limit)
        out += fmt::format("; removing the largest parts until the rest meets it takes {}, leaving {:.1f}x\n",
                           removed, left);
    else
        out += fmt::format("; even with every other part removed, the targets' own answers take {:.1f}x\n", left);
    return out;
}

// CPU µs per case of `corpus generate --family uniform`, the text written to
// nowhere: median of `repetitions` runs of `count` cases.
struct generation_timing {
    double us_per_case = 0;     // median
    double bytes_per_case = 0;  // of the text written
};
generation_timing time_uniform_generation(int repetitions, std::size_t count) {
    std::vector<double> us;
    std::size_t bytes = 0;
    for (int r = 0; r < repetitions; ++r) {
        bytes = 0;
        const double start = cpu_seconds();
        write_generated_corpus("uniform", count, 1, [&](std::string_view piece) { bytes += piece.size(); });
        us.push_back((cpu_seconds() - start) * 1e6 / double(count));
        if (bytes == 0) throw std::logic_error("corpus generate wrote nothing");
    }
    return {bench::median_of(us), static_cast<double>(bytes) / static_cast<double>(count)};
}

}  // namespace

int run_audit_timing(const std::vector<corpus_case>& cases, int repetitions, double min_time_s) {
    const std::vector<audit_target> targets = select_targets(ratio_variants, {"float", "double"});
    std::map<std::string, std::vector<corpus_case>> by_family;
    for (const corpus_case& c : cases) by_family[c.family.empty() ? "-" : c.family].push_back(c);
    std::vector<audit_timing_row> rows;
    for (const auto& [family, members] : by_family) {
        fmt::print(stderr, "bench --audit: {} ({} cases)\n", family, members.size());
        rows.push_back(time_family(family, members, targets, repetitions, min_time_s));
    }
    rows.push_back(time_family("all", cases, targets, repetitions, min_time_s));
    fmt::print("{}", format_rows(rows, targets.size(), repetitions));
    fmt::print("{}", format_parts(rows));

    fmt::print("targets, this run:\n");
    const auto target = [](const std::string& what, double value, double limit) {
        fmt::print("  {:<52} {:>8.2f}x  target <= {:g}x  {}\n", what, value, limit, value <= limit ? "met" : "MISSED");
        return value <= limit;
    };
    for (const audit_timing_row& r : rows) {
        const bool ordinary = r.family == "uniform" || r.family == "far_sphere";
        const double limit = ordinary ? 40 : 200;
        if (r.family != "all" && !target(fmt::format("audit / naive double, {}", r.family), r.audit_ratio, limit))
            fmt::print("{}", what_it_would_take(r.parts, r.audit_ratio, limit));
    }
    const audit_timing_row& all = rows.back();
    if (!target("per-case output / audit, all", all.per_case_ratio, 2)) {
        const double lines_ns = (all.per_case_ratio - 1) * all.audit_ns;  // per case-target
        fmt::print("      the lines cost {:.0f} ns per case-target beside the audit's {:.0f} ({:.0f} bytes, {:.2f} ns a "
                   "byte); meeting it needs them {:.0f}% cheaper\n",
                   lines_ns, all.audit_ns, all.per_case_bytes, lines_ns / all.per_case_bytes,
                   100 * (1 - all.audit_ns / lines_ns));
    }
    const generation_timing generation = time_uniform_generation(repetitions, 20000);
    const bool generation_met = generation.us_per_case <= 1;
    fmt::print("  {:<52} {:>7.2f}us  target <= 1us  {}\n", "corpus generate, uniform, per case", generation.us_per_case,
               generation_met ? "met" : "MISSED");
    if (!generation_met)
        fmt::print("      {:.0f} bytes of text per case, {:.2f} ns a byte; meeting it needs {:.0f}% less\n",
                   generation.bytes_per_case, 1e3 * generation.us_per_case / generation.bytes_per_case,
                   100 * (1 - 1 / generation.us_per_case));
    fmt::print("build: {}; CPU: {}\n", build_summary(), bench::cpu_model());
    return exit_ok;
}

}  // namespace rayverify::cli
