// Exact dyadic rationals and quadratic irrationals (internal/exact_number.h).
#include "oracle/internal/exact_number.h"

#include <cmath>

namespace rayverify::oracle_internal {

exact power_of_two(long k) {
    exact result(1.0);
    const exact big_step(std::ldexp(1.0, 1000)), small_step(std::ldexp(1.0, -1000));
    for (; k > 1000; k -= 1000) result = result * big_step;
    for (; k < -1000; k += 1000) result = result * small_step;
    return result * exact(std::ldexp(1.0, static_cast<int>(k)));
}

exact midpoint(double lo, double hi) { return (exact(lo) + exact(hi)) * exact(0.5); }

int sign_of_sum_with_root(const exact& A, const exact& B, const exact& D) {
    const int sign_a = sign_of(A);
    const int sign_root = D.is_zero() ? 0 : sign_of(B);
    if (sign_root == 0) return sign_a;
    if (sign_a == 0 || sign_a == sign_root) return sign_root;
    // Opposite signs: the larger of |A| and |B|·√D wins; compare their squares.
    const exact a_squared = A * A;
    const exact root_term_squared = B * B * D;
    if (a_squared == root_term_squared) return 0;
    return a_squared > root_term_squared ? sign_a : sign_root;
}

// For x = (A1 + B1√D1)/den1, y = (A2 + B2√D2)/den2: with
// P = A1·den2 − A2·den1, Q = B1·den2, R = −B2·den1, sign(x − y) is the sign of
// u + v, u = P + Q√D1, v = R√D2. When u and v have opposite signs the larger
// magnitude wins: u² − v² = (P² + Q²D1 − R²D2) + 2PQ√D1, one more square root
// term, whose sign sign_of_sum_with_root decides.
int sign_of_difference(const quadratic_irrational& x, const quadratic_irrational& y) {
    const exact P = x.A * y.den - y.A * x.den, Q = x.B * y.den, R = -(y.B * x.den);
    const int sign_u = sign_of_sum_with_root(P, Q, x.D);
    const int sign_v = y.D.is_zero() ? 0 : sign_of(R);
    if (sign_v == 0) return sign_u;
    if (sign_u == 0 || sign_u == sign_v) return sign_v;
    const int larger_u = sign_of_sum_with_root(P * P + Q * Q * x.D - R * R * y.D, exact(2.0) * P * Q, x.D);
    if (larger_u == 0) return 0;
    return larger_u > 0 ? sign_u : sign_v;
}

std::shared_ptr<const exact_quadratic> exact_quadratic_of(const ray_sphere<double>& g, bool unit_direction,
                                                          const vec3<double>& direction_low) {
    auto q = std::make_shared<exact_quadratic>();
    const double o[3] = {g.origin.x, g.origin.y, g.origin.z};
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const double c[3] = {g.centre.x, g.centre.y, g.centre.z};
    exact a(0.0), b_prime(0.0), f_squared(0.0);
    for (int axis = 0; axis < 3; ++axis) {
        q->origin[axis] = exact(o[axis]);
        q->direction[axis] = direction_low[axis] == 0 ? exact(d[axis]) : exact(d[axis]) + exact(direction_low[axis]);
        const exact f = q->origin[axis] - exact(c[axis]);
        a = a + q->direction[axis] * q->direction[axis];
        b_prime = b_prime + q->direction[axis] * f;
        f_squared = f_squared + f * f;
    }
    if (unit_direction) a = exact(1.0);
    const exact r(g.radius);
    const exact C = f_squared - r * r;
    q->discriminant = b_prime * b_prime - a * C;
    // Roots (−b′ ∓ √Δ′)/a.
    q->near_root = {-b_prime, exact(-1.0), q->discriminant, a};
    q->far_root = {-b_prime, exact(1.0), q->discriminant, a};
    return q;
}

}  // namespace rayverify::oracle_internal
