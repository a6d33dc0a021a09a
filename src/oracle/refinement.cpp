// Exact signs and refined roots from expansions (refinement.h).
#include "oracle/refinement.h"

#include <cmath>

#include "core/fma_clones.h"

namespace rayverify::oracle_internal {

// Each coefficient compressed once (Shewchuk's Compress: the same value in
// fewer components), which every later product with a double pays for.
RAYVERIFY_CLONED_FOR_FMA void form_coefficients(exact_coefficients& k, const ray_sphere<double>& g,
                                                bool unit_direction) {
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    for (int axis = 0; axis < 3; ++axis) add_into(k.f[axis], expansion_of(g.origin[axis]), expansion_of(-g.centre[axis]));
    const expansion<2>* f = k.f;
    if (unit_direction)
        k.a = expansion<6>(expansion_of(1.0));
    else
        compress_into(k.a, expansion_of(d[0]) * d[0] + expansion_of(d[1]) * d[1] + expansion_of(d[2]) * d[2]);
    compress_into(k.two_b_prime, f[0] * (2 * d[0]) + f[1] * (2 * d[1]) + f[2] * (2 * d[2]));
    k.radius = g.radius;
}

RAYVERIFY_CLONED_FOR_FMA expansion<26> constant_term_of(const exact_coefficients& k) {
    const expansion<2>* f = k.f;
    return compressed(f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - expansion_of(k.radius) * k.radius);
}

namespace {

// Δ′ as an expansion, times 4 with `unit_direction` (4Δ′ = (2b′)² − 4C, with
// a taken to be 1), else a·r² − |d × f|² (Lagrange's identity).
expansion<408> scaled_discriminant(const ray_sphere<double>& g, const exact_coefficients& k, bool unit_direction) {
    if (unit_direction) return expansion<408>(k.two_b_prime * k.two_b_prime - k.C() * 4.0);
    const double d[3] = {g.direction.x, g.direction.y, g.direction.z};
    const expansion<2>* f = k.f;
    const expansion<8> cross[3] = {compressed(f[2] * d[1] - f[1] * d[2]), compressed(f[0] * d[2] - f[2] * d[0]),
                                   compressed(f[1] * d[0] - f[0] * d[1])};
    return k.a * (expansion_of(g.radius) * g.radius) - (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
}

}  // namespace

RAYVERIFY_CLONED_FOR_FMA exact_discriminant discriminant_of(const ray_sphere<double>& g, const exact_coefficients& k,
                                                            bool unit_direction) {
    const expansion<408> scaled = scaled_discriminant(g, k, unit_direction);
    const bounded approximation = approximate(scaled);
    if (!unit_direction) return {sign_of(scaled), approximation};
    // Scaled back by 1/4, exactly.
    return {sign_of(scaled), {{approximation.v.h * 0.25, approximation.v.l * 0.25}, approximation.err * 0.25}};
}

RAYVERIFY_CLONED_FOR_FMA int discriminant_side(const ray_sphere<double>& g, const exact_coefficients& k,
                                               bool unit_direction, double x) {
    return sign_of(scaled_discriminant(g, k, unit_direction) - expansion_of(unit_direction ? 4 * x : x));
}

// Every component of P(u) then stays above 2^−720 and below 2^570.
bool refinable(double u) { return u == 0 || (std::fabs(u) >= 0x1p-200 && std::fabs(u) <= 0x1p200); }

RAYVERIFY_CLONED_FOR_FMA int tangent_root_side(const exact_coefficients& k, double m) {
    return -sign_of(k.two_b_prime + (k.a * m) * 2.0);
}

RAYVERIFY_CLONED_FOR_FMA int root_side(const exact_coefficients& k, double m, int other_side) {
    const int p = sign_of((k.a * m) * m + k.two_b_prime * m + k.C());  // sign(m − t_i)·sign(m − t_j)
    return -p * -other_side;
}

RAYVERIFY_CLONED_FOR_FMA int tangent_hit_side(const exact_coefficients& k, double o, double d, double v) {
    const expansion<2> offset = expansion_of(o) - expansion_of(v);
    return sign_of((k.a * offset) * 2.0 - k.two_b_prime * d);
}

RAYVERIFY_CLONED_FOR_FMA int hit_side(const exact_coefficients& k, double o, double d, double v, int other_side) {
    const expansion<2> w = compressed(expansion_of(v) - expansion_of(o));
    return sign_of(k.a * (w * w) + (k.two_b_prime * w) * d + (k.C() * d) * d) * other_side;
}

namespace {

// base − t from numerator / denominator = base − t: the correction t − base
// with its bound, from the exact numerator's and denominator's approximations.
refined_enclosure correction_from(double base, const bounded& numerator, const bounded& denominator) {
    refined_enclosure out;
    const std::optional<bounded> offset = quotient(numerator, denominator);  // base − t
    if (!offset) return out;
    out.base = base;
    out.correction = {-offset->v.h, -offset->v.l, offset->err};
    return out;
}

}  // namespace

// With P(t) = a t² + 2b′t + C = a(t − t_i)(t − t_j), the correction from
// u = the enclosure's high word is t_i − u = −P(u) / (a (u − t_j)). P(u) is
// evaluated exactly as an expansion (degree 4 in the inputs and u: nothing
// rounds), so the correction, about 2^−53·|t_i|, is known to about 2^−100 of
// itself. Needs both roots' enclosures (hence the filter range for the
// inputs) and u refinable and nonzero; err = +inf otherwise, or when
// u − t_j's sign is uncertain (roots too close for the enclosures to part).
RAYVERIFY_CLONED_FOR_FMA refined_enclosure refine_root(const exact_coefficients& k, const enclosure& root,
                                                      const enclosure& other) {
    const double u = root.hi;
    if (!known(root) || !known(other) || u == 0 || !refinable(u)) return {};
    const expansion<74> P = (k.a * u) * u + k.two_b_prime * u + k.C();
    const bounded gap = exactly(u) - bounded_of(other);  // u − t_j
    return correction_from(u, approximate(P), approximate_compressed(k.a) * gap);
}

// For a tangent's root t = −b′/a: u − t = (2b′ + 2a·u) / 2a, the numerator exact.
RAYVERIFY_CLONED_FOR_FMA refined_enclosure refine_tangent_root(const exact_coefficients& k, const enclosure& root) {
    const double u = root.hi;
    if (!known(root) || u == 0 || !refinable(u)) return {};
    const expansion<36> numerator = k.two_b_prime + (k.a * u) * 2.0;
    return correction_from(u, approximate(numerator), approximate_compressed(k.a) * 2.0);
}

// (value − u) is exact, the correction carries the bound.
bounded root_difference(const refined_enclosure& t, double value) {
    return exactly(two_sum(value, -t.base)) - bounded_of(t.correction);
}

// (value − o − d·u) in double-words, whose operations err relative to the
// (small) result only, minus d·correction.
RAYVERIFY_CLONED_FOR_FMA bounded hit_difference(const refined_enclosure& t, double o, double d, double value) {
    const bounded residual = exactly(two_sum(value, -o)) - exactly(two_prod(d, t.base));
    return residual - bounded_of(t.correction) * d;
}

}  // namespace rayverify::oracle_internal
