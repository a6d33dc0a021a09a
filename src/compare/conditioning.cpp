#include "compare/conditioning.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/double_word.h"
#include "core/fma_clones.h"
#include "core/float_bits.h"

namespace rayverify {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

struct dd3 {
    dword x, y, z;
    dword operator[](int k) const { return k == 0 ? x : (k == 1 ? y : z); }
};

dword dot(const dd3& a, const dd3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The largest binary exponent among the values (for exact power-of-two scaling).
int max_exponent(std::initializer_list<double> values) {
    int e = std::numeric_limits<int>::min();
    for (double v : values)
        if (v != 0) e = std::max(e, binade_of(v));
    return e == std::numeric_limits<int>::min() ? 0 : e;
}

// κ's numerator Σ_k |p_k|·(|o_k| + |c_k| + |t|·|d_k|) + r² for root t (scaled
// coordinates, r² its double), see conditioning.h: κ = it / (√Δ′·|t|), κ·|t| = it / √Δ′.
double condition_numerator(dword t, const dd3& f, const dd3& o, const dd3& d, const dd3& c, double r_squared) {
    double numerator = r_squared;
    const double abs_t = std::fabs(dw_value(t));
    for (int k = 0; k < 3; ++k) {
        const double p = std::fabs(dw_value(f[k] + t * d[k]));
        numerator += p * (std::fabs(dw_value(o[k])) + std::fabs(dw_value(c[k])) + abs_t * std::fabs(dw_value(d[k])));
    }
    return numerator;
}

}  // namespace

// Some sixty double-word products (each an std::fma or two): cloned for FMA
// hardware, where the library's fma call had made this a quarter of the
// audit's verdicts. The same bits on both clones.
RAYVERIFY_CLONED_FOR_FMA stability_measures measure_stability(const ray_sphere<double>& input, precision prec,
                                                              const exact_solution& exact) {
    stability_measures m;
    if (!exact.valid()) return m;
    m.valid = true;
    m.cls = exact.cls;

    // Scale positions and the direction by powers of two (exact): κ, ρ and the
    // margin are invariant, and products of four inputs can neither overflow
    // nor underflow at the corpus' magnitudes.
    const auto& g = input;
    const int position_exponent = max_exponent({g.origin.x, g.origin.y, g.origin.z, g.centre.x, g.centre.y,
                                                g.centre.z, g.radius});
    const int direction_exponent = max_exponent({g.direction.x, g.direction.y, g.direction.z});
    // v·2^−e, correctly rounded (by one multiplication where 2^−e is a normal double).
    const auto scaled = [](double v, int e) {
        return -e >= -1022 && -e <= 1023 ? v * exact_power_of_two(-e) : std::ldexp(v, -e);
    };
    const auto position = [&](double v) { return dword{scaled(v, position_exponent), 0}; };
    const auto direction = [&](double v) { return dword{scaled(v, direction_exponent), 0}; };
    const dd3 o{position(g.origin.x), position(g.origin.y), position(g.origin.z)};
    const dd3 c{position(g.centre.x), position(g.centre.y), position(g.centre.z)};
    const dd3 d{direction(g.direction.x), direction(g.direction.y), direction(g.direction.z)};
    const dword r = position(g.radius);

    // Quadratic coefficients a t² + 2b′t + C (f = o − c is exact in dd).
    const dd3 f{two_sum(o.x.h, -c.x.h), two_sum(o.y.h, -c.y.h), two_sum(o.z.h, -c.z.h)};
    const dword a = dot(d, d);
    const dword b_prime = dot(d, f);
    const dword C = dot(f, f) - r * r;
    // Δ′ = a·r² − |d × f|² (Lagrange's identity), the oracle's form: b′² − aC
    // cancels for far spheres (at |f|/r = 10^15 it is off by several percent).
    const dd3 cross{f.z * d.y - f.y * d.z, f.x * d.z - f.z * d.x, f.y * d.x - f.x * d.y};
    const dword discriminant = a * (r * r) - dot(cross, cross);

    m.discriminant_sign = exact.cls == line_class::tangent ? 0 : (exact.cls == line_class::miss ? -1 : 1);
    const double abs_discriminant = m.cls == line_class::tangent ? 0 : std::fabs(dw_value(discriminant));
    m.tangency_distance = abs_discriminant / (dw_value(b_prime * b_prime) + std::fabs(dw_value(a * C)));

    // M = Σ |∂Δ′/∂x_i|·|x_i|.
    double sensitivity = dw_value(a * r * r);
    for (int k = 0; k < 3; ++k) {
        const double along = std::fabs(dw_value(b_prime * d[k] - a * f[k]));
        const double across = std::fabs(dw_value(b_prime * f[k] - C * d[k]));
        sensitivity += along * (std::fabs(dw_value(o[k])) + std::fabs(dw_value(c[k]))) + across * std::fabs(dw_value(d[k]));
    }
    sensitivity *= 2;
    const double u = unit_roundoff(prec);
    m.tangency_margin = sensitivity > 0 ? abs_discriminant / (u * sensitivity) : infinity;
    m.distance_ratio = std::sqrt(dw_value(dot(f, f))) / dw_value(r);

    if (m.cls == line_class::miss) return m;
    if (m.cls == line_class::tangent) {
        m.near_condition = m.far_condition = infinity;
        m.near_absolute_condition = m.far_absolute_condition = infinity;
        m.near_root = std::ldexp(dw_value(-b_prime / a), position_exponent - direction_exponent);
        return m;
    }
    // Stable roots: q = −(b′ + sign(b′)√Δ′), roots q/a and C/q.
    const dword sqrt_discriminant = dw_sqrt(discriminant.h < 0 ? -discriminant : discriminant);
    const dword q = b_prime.h >= 0 ? -(b_prime + sqrt_discriminant) : sqrt_discriminant - b_prime;
    dword t_near = q / a, t_far = C / q;
    if (dw_value(t_near) > dw_value(t_far)) std::swap(t_near, t_far);
    m.near_root = std::ldexp(dw_value(t_near), position_exponent - direction_exponent);
    const bool resolved = dw_value(discriminant) > 0;  // dd resolves Δ′ (else κ is beyond its reach)
    // κ = numerator / (√Δ′·|t|), and κ·|t| = numerator / √Δ′ in the inputs'
    // own units (t scales by 2^(position − direction exponent)): the
    // numerator formed once per root for both.
    const double r_squared = dw_value(r * r);
    const auto set_conditions = [&](dword t, int sign, std::optional<double>& kappa,
                                    std::optional<double>& absolute_kappa) {
        if (!resolved) {
            kappa = absolute_kappa = infinity;
            return;
        }
        const double numerator = condition_numerator(t, f, o, d, c, r_squared);
        kappa = sign == 0 ? infinity : numerator / (dw_value(sqrt_discriminant) * std::fabs(dw_value(t)));
        absolute_kappa = std::ldexp(numerator / dw_value(sqrt_discriminant), position_exponent - direction_exponent);
    };
    set_conditions(t_near, exact.near_root.sign, m.near_condition, m.near_absolute_condition);
    set_conditions(t_far, exact.far_root.sign, m.far_condition, m.far_absolute_condition);
    return m;
}

}  // namespace rayverify
