#include "report/audit_timing_report.h"

#include <algorithm>

#include <fmt/format.h>

#include "bench/timing.h"
#include "intersectors/registry.h"
#include "report/audit_report.h"

namespace rayverify {
namespace {

using bench::audit_parts;
using bench::audit_timing_row;

double share(std::uint64_t part, std::uint64_t whole) { return whole ? 100.0 * double(part) / double(whole) : 0; }

std::string format_rows(const bench::audit_timing& timing) {
    std::string out = fmt::format("{:<15} {:>5} {:>8} {:>11} {:>11} {:>8}", "family", "cases", "naive_ns", "audit_ns/ct",
                                  "audit/naive", "per-case");
    for (const char* kind : {"solve", "ulp", "cmp", "round"})
        out += fmt::format(" {:>9} {:>8}", fmt::format("{}_exp", kind), fmt::format("{}_ex", kind));
    out += '\n';
    for (const audit_timing_row& r : timing.rows) {
        const oracle_stage_counts& c = r.counts;
        out += fmt::format("{:<15} {:>5} {:>8.2f} {:>11.1f} {:>10.1f}x {:>7.2f}x", r.family, r.cases, r.naive_ns,
                           r.audit_ns, r.audit_ratio, r.per_case_ratio);
        for (const stage_tally* t : {&c.solutions, &c.ulp_errors, &c.comparisons, &c.roundings})
            out += fmt::format(" {:>8.2f}% {:>7.2f}%", share(t->expansion, t->total()), share(t->exact, t->total()));
        out += '\n';
    }
    out += fmt::format(
        "audit_ns/ct = CPU ns per case-target of the audit as `rayverify audit --report` runs it (oracle, {} "
        "targets: the {} textbook variants in float and double, judge, stability, plot sample), one thread, median "
        "of {} repetitions; audit/naive and per-case (the audit writing --per-case lines, over the audit alone) are "
        "medians of each repetition's ratio of neighbouring timings; *_exp, *_ex = share "
        "of the oracle's answers of each kind (solutions of float and double inputs, ULP errors of roots and "
        "hit-point coordinates, comparisons with a value, rounded hit coordinates) that needed floating-point "
        "expansions (no big numbers) or exact arithmetic (GMP); the rest the filters (static, then double-word) settled.\n",
        timing.target_count, textbook_variant_names().size(), timing.repetitions);
    return out;
}

// Where each family's audit time goes: the parts in multiples of naive.
std::string format_parts(const bench::audit_timing& timing) {
    std::string out = "where the audit's time goes, x naive double per case-target (medians of each repetition's ratios):\n";
    out += fmt::format("{:<15}", "family");
    for (const auto& [name, value] : timing.rows.front().parts.named()) out += fmt::format(" {:>11}", name);
    out += fmt::format(" {:>11} {:>11}\n", "sum", "audit");
    for (const audit_timing_row& r : timing.rows) {
        out += fmt::format("{:<15}", r.family);
        for (const auto& [name, value] : r.parts.named()) out += fmt::format(" {:>10.1f}x", value);
        out += fmt::format(" {:>10.1f}x {:>10.1f}x\n", r.parts.sum(), r.audit_ratio);
    }
    out += fmt::format("targets = the {} targets' own answers; oracle = solve_case on the double and the float inputs; "
                       "verdicts = ", timing.target_count);
    out += "audit_case asked for verdicts alone (figure_request::verdict_only) less those two (outputs widened, "
           "verdicts and their causes, and each case's frame, formed once per precision and shared by the targets: "
           "its stability measures, unit-direction checks); figures = audit_case less that (every error figure of "
           "every agreeing answer, exactly: root, hit-point and scale errors, bits, bounds); accumulate = "
           "audit_stream less audit_case (tallies, error histograms); stability = the whole pass less audit_stream "
           "(stability tallies, plot sample, contract lint, example cases). The last four are differences of "
           "timings, so noise can leave one a little below 0.\n";
    return out;
}

// For a target the audit missed: how far off it is and what meeting it would
// take, from this run's parts: the share of the time that must go, and the
// largest parts that would have to go entirely for the rest to meet it.
std::string what_it_would_take(const audit_parts& parts, double ratio, double limit) {
    std::vector<std::pair<std::string, double>> largest = parts.named();
    std::sort(largest.begin(), largest.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    std::string out = fmt::format("      needs {:.1f}x of {:.1f}x gone ({:.0f}%)", ratio - limit, ratio,
                                  100 * (ratio - limit) / ratio);
    double left = parts.sum();
    // The parts and the whole are medians of separate timings: their sum
    // may meet the target where the whole does not, and then no part need go.
    if (left <= limit)
        return out + fmt::format("; its parts sum to {:.1f}x, within the target: the {:.1f}x beyond them is the "
                                 "difference between separately timed medians, not a part to remove\n",
                                 left, ratio - left);
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

bool cost_met(double value, double limit) { return bench::target_met(value, limit, bench::target_direction::at_most); }

// "  what   1.23x  target <= 4x  met" and, when missed, why.
std::string goal_line(const std::string& what, double value, double limit) {
    return fmt::format("  {:<52} {:>8.2f}x  target <= {:g}x  {}\n", what, value, limit,
                       cost_met(value, limit) ? "met" : "MISSED");
}

}  // namespace

std::string audit_timing_text(const bench::audit_timing& timing) {
    const bench::audit_cost_goals& goals = timing.goals;
    std::string out = format_rows(timing) + format_parts(timing);
    out += "targets, this run:\n";
    for (const audit_timing_row& r : timing.rows) {
        if (r.family == "all") continue;
        const double limit = goals.limit_for(r.family);
        out += goal_line(fmt::format("audit / naive double, {}", r.family), r.audit_ratio, limit);
        if (!cost_met(r.audit_ratio, limit)) out += what_it_would_take(r.parts, r.audit_ratio, limit);
    }
    const audit_timing_row& all = timing.rows.back();
    out += goal_line("per-case output / audit, all", all.per_case_ratio, goals.per_case_lines);
    if (!cost_met(all.per_case_ratio, goals.per_case_lines)) {
        const double lines_ns = (all.per_case_ratio - 1) * all.audit_ns;  // per case-target
        out += fmt::format("      the lines cost {:.0f} ns per case-target beside the audit's {:.0f} ({:.0f} bytes, "
                           "{:.2f} ns a byte, each disagreement's sentence among them, which the audit alone "
                           "leaves unformed); meeting it needs them {:.0f}% cheaper\n",
                           lines_ns, all.audit_ns, all.per_case_bytes, lines_ns / all.per_case_bytes,
                           100 * (1 - all.audit_ns / lines_ns));
    }
    const bench::generation_timing& generation = timing.generation;
    const bool generation_met = cost_met(generation.us_per_case, goals.generation_us);
    out += fmt::format("  {:<52} {:>7.2f}us  target <= {:g}us  {}\n", "corpus generate, uniform, per case",
                       generation.us_per_case, goals.generation_us, generation_met ? "met" : "MISSED");
    if (!generation_met)
        out += fmt::format("      {:.0f} bytes of text per case, {:.2f} ns a byte; meeting it needs {:.0f}% less\n",
                           generation.bytes_per_case, 1e3 * generation.us_per_case / generation.bytes_per_case,
                           100 * (1 - goals.generation_us / generation.us_per_case));
    out += fmt::format("build: {}; CPU: {}\n", build_summary(), bench::cpu_model());
    return out;
}

}  // namespace rayverify
