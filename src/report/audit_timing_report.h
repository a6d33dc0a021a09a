// `bench --audit` as text: the per-family table of the audit's cost and the
// oracle's stages, where the time goes, and each goal with met or MISSED and,
// for a missed one, what meeting it would take (from the same run's figures).
#pragma once

#include <string>

#include "bench/audit_timing.h"

namespace rayverify {

std::string audit_timing_text(const bench::audit_timing& timing);

}  // namespace rayverify
