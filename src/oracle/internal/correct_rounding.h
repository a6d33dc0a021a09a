// Correct rounding in the exact route: RN(x) of a quadratic irrational in a
// binary format, and the ULP error of a double against it, every digit
// right. MPFR only proposes (a first guess, a binade, an error magnitude);
// every proposal is verified by exact comparison against the rounding
// boundaries (midpoints, ties to even, the overflow threshold) before it is
// used.
//
// Private to the oracle (internal/exact_number.h's types; not installed).
#pragma once

#include "oracle/internal/exact_number.h"

namespace rayverify::oracle_internal {

// RN(x) in precision p (round to nearest, ties to even; ±inf past the
// overflow threshold), as a double.
double round_in(precision p, const quadratic_irrational& x);

// |value − x| / ulp(x) in precision p (ulp as core/float_bits.h defines it),
// every printed digit right; 0 exactly when value == x; +inf for a
// non-finite value.
double ulp_error_in(precision p, const quadratic_irrational& x, double value);

// sign(|value − x| / ulp(x) − bound) in precision p, exactly (ulp as
// ulp_error_in's); value finite, bound finite and ≥ 0.
int compare_ulp_error_in(precision p, const quadratic_irrational& x, double value, double bound);

}  // namespace rayverify::oracle_internal
