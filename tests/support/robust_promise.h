// What robust_sphere.h promises to return for an exact root, shared by the
// tests that check it against the oracle (robust_sphere_test, robust_audit_test).
#pragma once

#include <cmath>
#include <limits>
#include <type_traits>

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

// The bounded tier's promise for a root of T, against the value the correctly
// rounded tier promises: float, that value itself; double, within 2^-44 of it
// (2^-44·|t*| of t*, less half an ulp) and on its side.
template <class T>
bool within_bound(T got, T promised) {
    if (std::is_same_v<T, float> || promised == 0 || std::isinf(promised))
        return got == promised && std::signbit(got) == std::signbit(promised);
    return std::fabs(double(got) - double(promised)) <= 0x1p-44 * std::fabs(double(promised)) &&
           std::signbit(got) == std::signbit(promised);
}

}  // namespace rayverify::test_support
