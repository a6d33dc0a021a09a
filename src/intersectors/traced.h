// traced<T>: a scalar that carries, beside the value an intersector computes
// in T, the ideal value of the same expression on the same (exact) inputs,
// so that `explain` can show where the bits went, step by step, from the
// variant's own code (intersectors/scalar_math.h).
//
// The computed side is bit for bit what the plain float or double
// instantiation computes: each operator is the one rounded operation of T
// (the build's -ffp-contract=off holds here too), fma is std::fma, one
// rounding. Comparisons and branches look at the computed value only, so a
// traced run takes the variant's own path.
//
// The ideal side is kept by an ideal_arithmetic behind opaque handles (the
// oracle's implementation, oracle/ideal_arithmetic.h, holds it in MPFR);
// nothing here depends on how. An input or a constant of the formula is
// exact as computed (`exact_as_computed`) and costs nothing until an
// operation needs it. With no trace_session on the thread, a traced run
// computes its values alone.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "core/vec3.h"
#include "intersectors/scalar_math.h"

namespace rayverify {

using ideal_id = std::uint32_t;
inline constexpr ideal_id exact_as_computed = 0xffffffffu;

// The ideal operations, each on handles it gave out.
class ideal_arithmetic {
public:
    virtual ~ideal_arithmetic() = default;
    virtual ideal_id exactly(double value) = 0;
    virtual ideal_id add(ideal_id x, ideal_id y) = 0;
    virtual ideal_id subtract(ideal_id x, ideal_id y) = 0;
    virtual ideal_id multiply(ideal_id x, ideal_id y) = 0;
    virtual ideal_id divide(ideal_id x, ideal_id y) = 0;
    virtual ideal_id square_root(ideal_id x) = 0;
    virtual ideal_id fused_multiply_add(ideal_id x, ideal_id y, ideal_id z) = 0;
    virtual ideal_id negate(ideal_id x) = 0;
    virtual ideal_id absolute(ideal_id x) = 0;
    virtual ideal_id arc_tangent2(ideal_id y, ideal_id x) = 0;
};

// One named intermediate as a traced run met it.
struct traced_step {
    std::string name;
    double computed = 0;
    ideal_id ideal = exact_as_computed;
    int digits = 53;           // significand bits of the precision it was computed in
    double cancelled = 0;      // bits cancelled by the sum or difference that produced it; +inf: all
    bool subtraction = false;  // produced by a sum of opposite signs (a difference)
    std::string note;          // how the ideal side is formed, when not by the same operations
};

// The thread's trace: the ideal arithmetic and the steps recorded so far.
// Constructed around one traced run; restores the previous one when it ends.
class trace_session {
public:
    explicit trace_session(ideal_arithmetic& arithmetic) : ideal(arithmetic), previous_(slot()) { slot() = this; }
    ~trace_session() { slot() = previous_; }
    trace_session(const trace_session&) = delete;
    trace_session& operator=(const trace_session&) = delete;

    static trace_session* current() { return slot(); }
    ideal_id handle(double computed, ideal_id id) { return id == exact_as_computed ? ideal.exactly(computed) : id; }

    ideal_arithmetic& ideal;
    std::vector<traced_step> steps;

private:
    static trace_session*& slot() {
        thread_local trace_session* session = nullptr;
        return session;
    }
    trace_session* previous_;
};

// Bits of a p-bit significand a relative error leaves wrong: p + log2(error),
// 0 for an error within rounding, p (all) from an error of 1 (a value 0, or
// of the wrong sign) up.
inline double bits_lost(double relative_error, int digits) {
    if (std::isnan(relative_error)) return relative_error;
    if (relative_error == 0) return 0;
    const double lost = digits + std::log2(relative_error);
    return lost < 0 ? 0 : (lost > digits ? digits : lost);
}

// Bits a sum x + y of opposite signs cancels: log2(max(|x|, |y|)/|x + y|).
// The computed sum stands for the exact one: when a bit cancels, the
// difference is exact (Sterbenz).
inline double cancelled_bits(double x, double y, double sum) {
    if (x == 0 || y == 0 || std::signbit(x) == std::signbit(y)) return 0;
    if (sum == 0) return std::numeric_limits<double>::infinity();
    const double larger = std::fabs(x) > std::fabs(y) ? std::fabs(x) : std::fabs(y);
    const double bits = std::log2(larger / std::fabs(sum));
    return bits > 0 ? bits : 0;
}

template <class T>
struct traced {
    static_assert(std::is_floating_point_v<T>);
    using plain_type = T;

    T value{};
    ideal_id ideal = exact_as_computed;
    float cancelled = 0;  // of the operation that produced value (cancelled_bits), for its step
    bool subtraction = false;

    constexpr traced() = default;
    // An input or a constant of the formula: exact as T holds it.
    template <class A>
        requires std::is_arithmetic_v<A>
    constexpr traced(A v) : value(static_cast<T>(v)) {}
    // A change of precision: rounded as static_cast rounds; the ideal value is the expression's.
    template <class U>
        requires(!std::is_same_v<U, T>)
    explicit traced(traced<U> v) : value(static_cast<T>(v.value)) {
        if (v.ideal != exact_as_computed)
            ideal = v.ideal;
        else if (static_cast<U>(value) != v.value)
            if (trace_session* s = trace_session::current()) ideal = s->ideal.exactly(static_cast<double>(v.value));
    }

    // The computed value with an ideal handle given apart (a step whose code cannot run traced).
    static traced with_ideal(T computed, ideal_id id) {
        traced r{computed};
        r.ideal = id;
        return r;
    }

    friend traced operator+(traced x, traced y) { return sum(x, y, y.value, &ideal_arithmetic::add); }
    friend traced operator-(traced x, traced y) { return sum(x, y, -y.value, &ideal_arithmetic::subtract); }
    friend traced operator*(traced x, traced y) {
        return binary(x.value * y.value, x, y, &ideal_arithmetic::multiply);
    }
    friend traced operator/(traced x, traced y) { return binary(x.value / y.value, x, y, &ideal_arithmetic::divide); }
    friend traced operator-(traced x) { return unary(-x.value, x, &ideal_arithmetic::negate); }
    traced& operator+=(traced y) { return *this = *this + y; }
    traced& operator-=(traced y) { return *this = *this - y; }
    traced& operator*=(traced y) { return *this = *this * y; }

    friend traced sqrt(traced x) { return unary(std::sqrt(x.value), x, &ideal_arithmetic::square_root); }
    friend traced abs(traced x) { return unary(std::abs(x.value), x, &ideal_arithmetic::absolute); }
    friend traced fabs(traced x) { return abs(x); }
    friend traced fma(traced x, traced y, traced z) {
        traced r{std::fma(x.value, y.value, z.value)};
        if (trace_session* s = trace_session::current())
            r.ideal = s->ideal.fused_multiply_add(s->handle(x.value, x.ideal), s->handle(y.value, y.ideal),
                                                  s->handle(z.value, z.ideal));
        return r;
    }
    // The sign is chosen from the computed y, as the variant chose it.
    friend traced copysign(traced x, traced y) {
        const traced magnitude = abs(x);
        return std::signbit(y.value) ? -magnitude : magnitude;
    }
    friend traced atan2(traced y, traced x) {
        return binary(std::atan2(y.value, x.value), y, x, &ideal_arithmetic::arc_tangent2);
    }
    friend bool isinf(traced x) { return std::isinf(x.value); }
    friend bool isnan(traced x) { return std::isnan(x.value); }
    friend bool signbit(traced x) { return std::signbit(x.value); }

    // Comparisons decide on the computed value, against another traced value
    // or a plain number compared as T and that number would be compared.
    // constexpr: vec3's defaulted, constexpr == compares them (clang requires it).
    friend constexpr bool operator==(traced x, traced y) { return x.value == y.value; }
    friend constexpr auto operator<=>(traced x, traced y) { return x.value <=> y.value; }
    template <class A>
        requires std::is_arithmetic_v<A>
    friend constexpr bool operator==(traced x, A y) {
        return x.value == y;
    }
    template <class A>
        requires std::is_arithmetic_v<A>
    friend constexpr auto operator<=>(traced x, A y) {
        return x.value <=> y;
    }

private:
    using binary_op = ideal_id (ideal_arithmetic::*)(ideal_id, ideal_id);
    using unary_op = ideal_id (ideal_arithmetic::*)(ideal_id);

    static traced binary(T computed, traced x, traced y, binary_op op) {
        traced r{computed};
        if (trace_session* s = trace_session::current())
            r.ideal = (s->ideal.*op)(s->handle(x.value, x.ideal), s->handle(y.value, y.ideal));
        return r;
    }
    static traced unary(T computed, traced x, unary_op op) {
        traced r{computed};
        if (trace_session* s = trace_session::current()) r.ideal = (s->ideal.*op)(s->handle(x.value, x.ideal));
        return r;
    }
    // x + y or x − y, y_signed being the second term as added; records the cancellation.
    static traced sum(traced x, traced y, T y_signed, binary_op op) {
        traced r = binary(x.value + y_signed, x, y, op);
        r.cancelled = static_cast<float>(cancelled_bits(x.value, y_signed, r.value));
        r.subtraction = x.value != 0 && y_signed != 0 && std::signbit(x.value) != std::signbit(y_signed);
        return r;
    }
};

template <class T>
inline constexpr bool is_traced_v = false;
template <class T>
inline constexpr bool is_traced_v<traced<T>> = true;

template <class T>
struct plain_scalar<traced<T>> {
    using type = T;
};
template <class T, class W>
struct same_form<traced<T>, W> {
    using type = traced<W>;
};

// A step whose computed value comes from code that cannot run traced (bit
// manipulation, double words): that value, with the ideal value of `model`,
// the expression the code computes or bounds.
template <class T>
traced<T> computed_apart(T computed, traced<T> model) {
    return traced<T>::with_ideal(computed, model.ideal == exact_as_computed && trace_session::current()
                                               ? trace_session::current()->ideal.exactly(model.value)
                                               : model.ideal);
}

// Records a named step: found by argument-dependent lookup beside
// intersectors/scalar_math.h's identity.
template <class T>
traced<T> step(const char* name, traced<T> v, const char* note = nullptr) {
    if (trace_session* s = trace_session::current())
        s->steps.push_back({name, static_cast<double>(v.value), v.ideal, std::numeric_limits<T>::digits, v.cancelled,
                            v.subtraction, note ? note : ""});
    return v;
}

template <class T>
vec3<traced<T>> step(const char* name, vec3<traced<T>> v) {
    const std::string base = name;
    step((base + ".x").c_str(), v.x);
    step((base + ".y").c_str(), v.y);
    step((base + ".z").c_str(), v.z);
    return v;
}

template <class T>
traced<T> rounding_error_bound(traced<T> bound) {
    trace_session* s = trace_session::current();
    return s ? traced<T>::with_ideal(bound.value, s->ideal.exactly(0)) : bound;
}

template <class T>
ray_sphere<traced<T>> traced_inputs(const ray_sphere<T>& s) {
    const auto lift = [](vec3<T> v) { return vec3<traced<T>>{v.x, v.y, v.z}; };
    return {lift(s.origin), lift(s.direction), lift(s.centre), s.radius};
}

template <class T>
ray_sphere<T> computed_values(const ray_sphere<traced<T>>& s) {
    const auto drop = [](vec3<traced<T>> v) { return vec3<T>{v.x.value, v.y.value, v.z.value}; };
    return {drop(s.origin), drop(s.direction), drop(s.centre), s.radius.value};
}

// parameter_of_point and segment_length compute in double words, which a
// traced scalar cannot run: their computed value comes from the real
// function on the computed values; the ideal value of t is (p − o)·d/(d·d)
// on the ideal p, and a segment's length is a chosen constant, exact.
template <class T>
traced<T> parameter_of_point(const ray_sphere<traced<T>>& s, vec3<traced<T>> p) {
    const T computed = parameter_of_point(computed_values(s), vec3<T>{p.x.value, p.y.value, p.z.value});
    trace_session* session = trace_session::current();
    if (!session) return computed;
    const traced<T> along = (p.x - s.origin.x) * s.direction.x + (p.y - s.origin.y) * s.direction.y +
                            (p.z - s.origin.z) * s.direction.z;
    const traced<T> length2 = s.direction.x * s.direction.x + s.direction.y * s.direction.y +
                              s.direction.z * s.direction.z;
    return traced<T>::with_ideal(computed, session->ideal.divide(session->handle(along.value, along.ideal),
                                                                 session->handle(length2.value, length2.ideal)));
}

template <class T>
traced<T> segment_length(const ray_sphere<traced<T>>& s) {
    return segment_length(computed_values(s));
}

}  // namespace rayverify

// The traced scalar's limits are T's, as traced values.
template <class T>
struct std::numeric_limits<rayverify::traced<T>> : std::numeric_limits<T> {
    static constexpr rayverify::traced<T> infinity() noexcept { return std::numeric_limits<T>::infinity(); }
    static constexpr rayverify::traced<T> max() noexcept { return std::numeric_limits<T>::max(); }
    static constexpr rayverify::traced<T> lowest() noexcept { return std::numeric_limits<T>::lowest(); }
    static constexpr rayverify::traced<T> min() noexcept { return std::numeric_limits<T>::min(); }
    static constexpr rayverify::traced<T> epsilon() noexcept { return std::numeric_limits<T>::epsilon(); }
    static constexpr rayverify::traced<T> denorm_min() noexcept { return std::numeric_limits<T>::denorm_min(); }
    static constexpr rayverify::traced<T> quiet_NaN() noexcept { return std::numeric_limits<T>::quiet_NaN(); }
};
