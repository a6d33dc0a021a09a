// One pass of an audit as `rayverify audit` runs it, for the audit command
// and for `bench --audit`, which times exactly this.
#pragma once

#include <functional>
#include <ostream>
#include <vector>

#include "compare/audit.h"
#include "report/shard_state.h"

namespace rayverify {

// Every case from `next` through the oracle and the targets
// (compare/audit_stream) on `threads` threads, each case's stability assessed,
// the plot sample kept when `with_points`, and, when `per_case` is not null,
// its per-case JSON line written there in input order, and when `failures`
// is not null, every case some target disagrees on as a corpus line, in
// input order; `observe`, when set, sees every audited case in input order
// with its index in the whole input; `route` is the oracle's. Returns the
// state of all the workers merged.
audit_state run_audit_pass(const case_source& next, const std::vector<audit_target>& targets, unsigned threads,
                           bool with_points, std::ostream* per_case,
                           const std::function<void(std::size_t done)>& progress = {},
                           std::ostream* failures = nullptr,
                           const std::function<void(const audited_case&, std::size_t index)>& observe = {},
                           oracle_route route = oracle_route::filtered);

}  // namespace rayverify
