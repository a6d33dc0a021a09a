// bench --audit: what a user waits for, the whole audit's cost per
// case-target against the naive double intersector, per family, with the
// share of each exact figure the filter settled.
#pragma once

#include <vector>

#include "core/ray_sphere_case.h"

namespace rayverify::cli {

// Times the audit (as `rayverify audit` runs it, one thread) of `cases` per
// family and over all of them, prints the table and the audit's cost targets, and
// returns exit_ok.
int run_audit_timing(const std::vector<corpus_case>& cases, int repetitions, double min_time_s);

}  // namespace rayverify::cli
