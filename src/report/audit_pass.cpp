#include "report/audit_pass.h"

#include <algorithm>
#include <string>

#include "compare/stability.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "report/audit_report.h"
#include "report/stability_report.h"

namespace rayverify {

audit_state run_audit_pass(const case_source& next, const std::vector<audit_target>& targets, unsigned threads,
                           bool with_points, std::ostream* per_case,
                           const std::function<void(std::size_t done)>& progress, std::ostream* failures,
                           const std::function<void(const audited_case&, std::size_t index)>& observe) {
    // Per thread: the state, and the chunk's rendered per-case lines (written in order).
    std::vector<per_worker<audit_state>> workers(threads, {audit_state(targets)});
    std::vector<std::string> lines(per_case != nullptr ? case_stream::default_chunk : 0);
    audit_hooks hooks;
    hooks.parallel = [&](const audited_case& c, std::size_t index, std::size_t slot, unsigned worker) {
        workers[worker].state.stability.add(c, index);
        if (with_points) workers[worker].state.points.add(c, index);
        workers[worker].state.lint.add(c);
        workers[worker].state.examples.add(c, index);
        if (per_case == nullptr) return;
        lines[slot] = per_case_line(c, targets, std::move(lines[slot]));
    };
    if (per_case != nullptr || failures != nullptr || observe)
        hooks.ordered = [&](const audited_case& c, std::size_t index, std::size_t slot) {
            if (observe) observe(c, index);
            if (per_case != nullptr) *per_case << lines[slot] << '\n';
            if (failures == nullptr) return;
            const bool failing = std::any_of(c.outcomes.begin(), c.outcomes.end(),
                                             [](const target_outcome& o) { return is_disagreement(o.score.verdict); });
            if (failing) *failures << format_case_line(*c.source) << '\n';
        };
    hooks.progress = progress;
    audit_state& state = workers[0].state;
    state.audit = audit_stream(next, targets, threads, hooks);
    for (unsigned w = 1; w < threads; ++w) {
        state.stability.merge(workers[w].state.stability);
        state.points.merge(workers[w].state.points);
        state.lint.merge(workers[w].state.lint);
        state.examples.merge(workers[w].state.examples);
    }
    return std::move(state);
}

}  // namespace rayverify
