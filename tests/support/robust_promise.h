// What robust_sphere.h promises to return for an exact root, shared by the
// tests that check it against the oracle (robust_sphere_test, robust_audit_test).
#pragma once

#include <limits>

#include "oracle/oracle.h"

namespace rayverify::test_support {

// Root i as robust_sphere.h must return it in T: RN(t*), but +denorm_min for
// a positive root that rounds to 0 (it stays in front) and −0 for a negative one.
template <class T>
T promised_root(const exact_solution& e, root_index i) {
    const exact_root& r = e.root(i);
    const T rn = static_cast<T>(r.rounded);
    if (rn == 0 && r.sign != 0) return r.sign > 0 ? std::numeric_limits<T>::denorm_min() : -T(0);
    return rn;
}

}  // namespace rayverify::test_support
