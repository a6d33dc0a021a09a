// Every built-in variant run in x87 extended precision (long double, 64-bit
// significand) on double inputs, its roots rounded to double: what a user
// gets by widening the arithmetic of a double renderer. The audit judges it
// as a double variant (exact roots of the double inputs, double ulps).
#pragma once

#include <vector>

#include "intersectors/registry.h"

namespace rayverify::bench {

// Same names, citations and contracts as the registry, for every variant
// written for long double (kernels.h, has_long_double); run_float is empty and
// run_double computes in long double.
std::vector<variant> long_double_variants();

}  // namespace rayverify::bench
