#include "report/audit_pass.h"

#include <string>

#include "compare/stability.h"
#include "corpus/case_stream.h"
#include "report/audit_report.h"
#include "report/stability_report.h"

namespace rayverify {

audit_state run_audit_pass(const case_source& next, const std::vector<audit_target>& targets, unsigned threads,
                           bool with_points, std::ostream* per_case,
                           const std::function<void(std::size_t done)>& progress) {
    // Per thread: the state, and the chunk's rendered per-case lines (written in order).
    std::vector<per_worker<audit_state>> workers(threads, {audit_state(targets)});
    std::vector<std::string> lines(per_case != nullptr ? case_stream::default_chunk : 0);
    audit_hooks hooks;
    hooks.parallel = [&](const audited_case& c, std::size_t index, std::size_t slot, unsigned worker) {
        const case_stability s = assess_case(c);
        workers[worker].state.stability.add(c, s, index);
        if (with_points) workers[worker].state.points.add(c, s, index);
        if (per_case == nullptr) return;
        lines[slot] = per_case_line(c, targets, s, std::move(lines[slot]));
    };
    if (per_case != nullptr)
        hooks.ordered = [&](const audited_case&, std::size_t, std::size_t slot) { *per_case << lines[slot] << '\n'; };
    hooks.progress = progress;
    audit_state& state = workers[0].state;
    state.audit = audit_stream(next, targets, threads, hooks);
    for (unsigned w = 1; w < threads; ++w) {
        state.stability.merge(workers[w].state.stability);
        state.points.merge(workers[w].state.points);
    }
    return std::move(state);
}

}  // namespace rayverify
