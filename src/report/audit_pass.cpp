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
                           const std::function<void(const audited_case&, std::size_t index)>& observe,
                           oracle_route route) {
    // Per thread: the state, and the storage a line is rendered in (json_line
    // sizes it generously once). Per slot of the chunk: the rendered per-case
    // line, copied to its own size, and the case's corpus line when some
    // target disagrees on it, both written in input order (the audited cases
    // themselves are not kept). With one worker the cases reach the parallel
    // hook in input order (one thread takes the chunk's cases in turn), so
    // each line is written as it is rendered and no slot is kept: a short
    // run's slots were each a fresh allocation, first touched, and a single-
    // threaded run's lines cost half as much again for them.
    struct worker_state {
        audit_state state;
        std::string rendering;
    };
    std::vector<per_worker<worker_state>> workers(threads, {worker_state{audit_state(targets), {}}});
    const bool written_as_rendered = audit_threads(targets, threads) == 1;
    const std::size_t slots = written_as_rendered ? 0 : case_stream::default_chunk;
    std::vector<std::string> lines(per_case != nullptr ? slots : 0);
    std::vector<std::string> failing_lines(failures != nullptr ? slots : 0);
    audit_hooks hooks;
    hooks.parallel = [&](const audited_case& c, std::size_t index, std::size_t slot, unsigned worker) {
        audit_state& state = workers[worker].state.state;
        state.stability.add(c, index);
        if (with_points) state.points.add(c, index);
        state.lint.add(c);
        state.examples.add(c, index, targets);
        if (per_case != nullptr) {
            std::string& rendering = workers[worker].state.rendering;
            rendering = per_case_line(c, targets, std::move(rendering));
            if (written_as_rendered)
                *per_case << rendering << '\n';
            else
                lines[slot].assign(rendering);
        }
        if (failures != nullptr) {
            const bool failing = std::any_of(c.outcomes.begin(), c.outcomes.end(),
                                             [](const target_outcome& o) { return is_disagreement(o.score.verdict); });
            if (written_as_rendered) {
                if (failing) *failures << format_case_line(*c.source) << '\n';
            } else {
                failing_lines[slot] = failing ? format_case_line(*c.source) : std::string();
            }
        }
    };
    if (observe) hooks.ordered = [&](const audited_case& c, std::size_t index, std::size_t) { observe(c, index); };
    if (!written_as_rendered && (per_case != nullptr || failures != nullptr))
        hooks.in_order = [&](std::size_t, std::size_t slot) {
            if (per_case != nullptr) *per_case << lines[slot] << '\n';
            if (failures != nullptr && !failing_lines[slot].empty()) *failures << failing_lines[slot] << '\n';
        };
    hooks.progress = progress;
    hooks.details = per_case != nullptr || static_cast<bool>(observe);  // the lines print it; an observer may read it
    audit_state& state = workers[0].state.state;
    state.audit = audit_stream(next, targets, threads, hooks, route);
    for (unsigned w = 1; w < threads; ++w) {
        const audit_state& other = workers[w].state.state;
        state.stability.merge(other.stability);
        state.points.merge(other.points);
        state.lint.merge(other.lint);
        state.examples.merge(other.examples);
    }
    return std::move(state);
}

}  // namespace rayverify
