// An independent reference for the exact oracle, written apart from it: plain
// MPFR at a working precision wide enough that every coefficient of the
// quadratic is computed exactly from double inputs (see mpfr_reference.cpp).
// It shares no code with oracle.cpp; tests require both to agree.
#pragma once

#include "core/ray_sphere_case.h"
#include "oracle/oracle.h"

namespace rayverify {

struct reference_answer {
    line_class cls = line_class::miss;
    int near_sign = 0, far_sign = 0;
    double near_rounded = 0, far_rounded = 0;  // RN to the given precision
};

// `geometry` must be valid at `prec` (finite, d ≠ 0, r ≥ 0).
reference_answer solve_with_mpfr_reference(const ray_sphere<double>& geometry, precision prec);

}  // namespace rayverify
