// The spelling every intersector uses for its math calls and its named
// steps, so that the same template runs on float, on double and on a traced
// scalar (intersectors/traced.h) that `explain` uses to show where the bits
// went.
//
// Math calls are unqualified (`sqrt(x)`, `fma(a, b, c)`, `copysign(x, y)`,
// `abs(x)`): for float and double these using-declarations pick std's
// overloads, the very functions `std::sqrt` names; for a traced scalar,
// argument-dependent lookup finds its own. numeric_limits is specialised for
// the traced scalar, so `std::numeric_limits<T>` stays as it is.
//
// `step("C", expr)` names an intermediate where the formula names it. For
// float and double it is the identity, inlined away: it changes neither an
// answer nor its speed.
#pragma once

#include <cmath>

namespace rayverify::intersectors {

using std::abs;
using std::atan2;
using std::copysign;
using std::fabs;
using std::fma;
using std::isinf;
using std::isnan;
using std::sqrt;

// A bound on rounding errors that a formula carries (pbrt's γ_n): itself;
// its ideal value is 0, since exact arithmetic makes no rounding error.
template <class T>
constexpr T rounding_error_bound(T bound) {
    return bound;
}

// An intermediate of the formula, named as the formula names it; `note`
// says how its ideal value is formed when a traced run cannot run its code.
template <class T>
constexpr T step(const char* /*name*/, T value, const char* /*note*/ = nullptr) {
    return value;
}

}  // namespace rayverify::intersectors

namespace rayverify {

// The float type a scalar computes in: T itself, or the T under a traced<T>.
template <class T>
struct plain_scalar {
    using type = T;
};
template <class T>
using plain_scalar_t = typename plain_scalar<T>::type;

// W in T's form: W for a plain T, a traced W for a traced T (a port that
// computes in a wider type than its inputs).
template <class T, class W>
struct same_form {
    using type = W;
};
template <class T, class W>
using same_form_t = typename same_form<T, W>::type;

}  // namespace rayverify
