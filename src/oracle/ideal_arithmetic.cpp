#include "oracle/ideal_arithmetic.h"

#include <mpfr.h>

#include <cmath>
#include <deque>
#include <limits>

namespace rayverify {

// One MPFR number per handle; a deque never moves what it holds.
struct exact_arithmetic::values {
    struct number {
        mpfr_t v;
        number() { mpfr_init2(v, precision_bits); }
        ~number() { mpfr_clear(v); }
        number(const number&) = delete;
        number& operator=(const number&) = delete;
    };
    std::deque<number> held;

    ideal_id make() {
        held.emplace_back();
        return static_cast<ideal_id>(held.size() - 1);
    }
    mpfr_ptr operator[](ideal_id id) { return held[id].v; }
};

exact_arithmetic::exact_arithmetic() : values_(std::make_unique<values>()) {}
exact_arithmetic::~exact_arithmetic() = default;

ideal_id exact_arithmetic::exactly(double value) {
    const ideal_id r = values_->make();
    mpfr_set_d((*values_)[r], value, MPFR_RNDN);
    return r;
}

#define RAYVERIFY_IDEAL_BINARY(name, mpfr_fn)                                      \
    ideal_id exact_arithmetic::name(ideal_id x, ideal_id y) {                      \
        const ideal_id r = values_->make();                                        \
        mpfr_fn((*values_)[r], (*values_)[x], (*values_)[y], MPFR_RNDN);           \
        return r;                                                                  \
    }
RAYVERIFY_IDEAL_BINARY(add, mpfr_add)
RAYVERIFY_IDEAL_BINARY(subtract, mpfr_sub)
RAYVERIFY_IDEAL_BINARY(multiply, mpfr_mul)
RAYVERIFY_IDEAL_BINARY(divide, mpfr_div)
RAYVERIFY_IDEAL_BINARY(arc_tangent2, mpfr_atan2)
#undef RAYVERIFY_IDEAL_BINARY

#define RAYVERIFY_IDEAL_UNARY(name, mpfr_fn)                          \
    ideal_id exact_arithmetic::name(ideal_id x) {                     \
        const ideal_id r = values_->make();                           \
        mpfr_fn((*values_)[r], (*values_)[x], MPFR_RNDN);             \
        return r;                                                     \
    }
RAYVERIFY_IDEAL_UNARY(square_root, mpfr_sqrt)
RAYVERIFY_IDEAL_UNARY(negate, mpfr_neg)
RAYVERIFY_IDEAL_UNARY(absolute, mpfr_abs)
#undef RAYVERIFY_IDEAL_UNARY

ideal_id exact_arithmetic::fused_multiply_add(ideal_id x, ideal_id y, ideal_id z) {
    const ideal_id r = values_->make();
    mpfr_fma((*values_)[r], (*values_)[x], (*values_)[y], (*values_)[z], MPFR_RNDN);
    return r;
}

step_figures exact_arithmetic::measure(const traced_step& s) {
    const ideal_id ideal = s.ideal == exact_as_computed ? exactly(s.computed) : s.ideal;
    mpfr_srcptr x = (*values_)[ideal];
    step_figures f;
    f.exact = mpfr_get_d(x, MPFR_RNDN);
    if (mpfr_nan_p(x) || std::isnan(s.computed)) {
        f.relative_error = f.bits_lost = std::numeric_limits<double>::quiet_NaN();
        return f;
    }
    if (mpfr_zero_p(x)) {
        f.relative_error = s.computed == 0 ? 0 : std::numeric_limits<double>::infinity();
    } else if (mpfr_inf_p(x) || std::isinf(s.computed)) {
        f.relative_error = mpfr_inf_p(x) && std::isinf(s.computed) && (mpfr_sgn(x) > 0) == (s.computed > 0)
                               ? 0
                               : std::numeric_limits<double>::infinity();
    } else {
        values::number error;
        mpfr_set_d(error.v, s.computed, MPFR_RNDN);
        mpfr_sub(error.v, error.v, x, MPFR_RNDN);
        mpfr_div(error.v, error.v, x, MPFR_RNDN);
        f.relative_error = std::fabs(mpfr_get_d(error.v, MPFR_RNDN));
    }
    f.bits_lost = bits_lost(f.relative_error, s.digits);
    return f;
}

}  // namespace rayverify
