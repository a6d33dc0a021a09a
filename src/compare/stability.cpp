#include "compare/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "core/double_word.h"
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

// κ of root t (scaled coordinates), see stability.h.
double condition_of(dword t, const dd3& f, const dd3& o, const dd3& d, const dd3& c, dword r, dword sqrt_discriminant) {
    double numerator = dw_value(r * r);
    const double abs_t = std::fabs(dw_value(t));
    for (int k = 0; k < 3; ++k) {
        const double p = std::fabs(dw_value(f[k] + t * d[k]));
        numerator += p * (std::fabs(dw_value(o[k])) + std::fabs(dw_value(c[k])) + abs_t * std::fabs(dw_value(d[k])));
    }
    return numerator / (dw_value(sqrt_discriminant) * abs_t);
}

}  // namespace

stability_measures measure_stability(const ray_sphere<double>& input, precision prec, const exact_solution& exact) {
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
    const double u = std::ldexp(1.0, -significand_bits(prec));
    m.tangency_margin = sensitivity > 0 ? abs_discriminant / (u * sensitivity) : infinity;
    m.distance_ratio = std::sqrt(dw_value(dot(f, f))) / dw_value(r);

    if (m.cls == line_class::miss) return m;
    if (m.cls == line_class::tangent) {
        m.near_condition = m.far_condition = infinity;
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
    const auto kappa = [&](dword t, int sign) {
        if (sign == 0 || !resolved) return infinity;
        return condition_of(t, f, o, d, c, r, sqrt_discriminant);
    };
    m.near_condition = kappa(t_near, exact.near_root.sign);
    m.far_condition = kappa(t_far, exact.far_root.sign);
    return m;
}

int condition_bucket(const stability_measures& s) {
    if (!s.near_condition) return condition_decades + 1;
    const double kappa = *s.near_condition;
    if (std::isinf(kappa)) return condition_decades;
    if (kappa < 10) return 0;
    return std::min(static_cast<int>(std::floor(std::log10(kappa))), condition_decades - 1);
}

std::string condition_bucket_label(int bucket) {
    if (bucket == condition_decades + 1) return "miss";
    if (bucket == condition_decades) return "inf";
    if (bucket == 0) return "<1e1";
    if (bucket == condition_decades - 1) return ">=1e" + std::to_string(bucket);
    return "1e" + std::to_string(bucket) + "..1e" + std::to_string(bucket + 1);
}

case_stability assess_case(const audited_case& c) {
    case_stability result;
    const auto measure = [&](precision p) {
        const exact_solution& exact = c.exact_for(p);
        const ray_sphere<double> input = p == precision::binary32
                                             ? rounded_to<double>(rounded_to<float>(c.source->geometry))
                                             : c.source->geometry;
        return measure_stability(input, p, exact);
    };
    result.at_double = measure(precision::binary64);
    if (c.exact_float) result.at_float = measure(precision::binary32);
    return result;
}

void stability_samples::merge(const stability_samples& other) {
    for (int b = 0; b < condition_bucket_count; ++b) {
        bucket_tally& mine = buckets[b];
        const bucket_tally& theirs = other.buckets[b];
        mine.cases += theirs.cases;
        mine.misclassified += theirs.misclassified;
        mine.disagreements += theirs.disagreements;
        mine.conditioning_limited += theirs.conditioning_limited;
        mine.algorithmic += theirs.algorithmic;
        mine.by_design += theirs.by_design;
        near_ulp[b].merge(other.near_ulp[b]);
    }
    excess.merge(other.excess);
    above_line += other.above_line;
    well_conditioned += other.well_conditioned;
    well_conditioned_above += other.well_conditioned_above;
}

stability_accumulator::stability_accumulator(std::vector<audit_target> t) : targets(std::move(t)) {}

void stability_accumulator::add(const audited_case& c, const case_stability& s, std::size_t index) {
    auto& family_samples = by_family[family_key(*c.source)];
    family_samples.resize(targets.size());
    const std::string& id = c.source->id;
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const case_score& score = c.outcomes[t].score;
        if (score.verdict == verdict_kind::invalid || score.verdict == verdict_kind::contract_violation) continue;
        const stability_measures& m = s.at(targets[t].prec);
        const int bucket = condition_bucket(m);
        stability_samples& out = family_samples[t];
        bucket_tally& b = out.buckets[bucket];
        ++b.cases;
        if (is_misclassification(score.verdict)) ++b.misclassified;
        if (is_disagreement(score.verdict)) ++b.disagreements;
        if (const auto& cause = score.cause) {
            if (*cause == disagreement_cause::conditioning_limited) ++b.conditioning_limited;
            if (*cause == disagreement_cause::algorithmic) ++b.algorithmic;
            if (is_by_design(*cause)) ++b.by_design;
        }
        if (score.verdict != verdict_kind::agree || !score.near_ulp) continue;
        figures_.push(out.near_ulp[bucket], *score.near_ulp);
        if (!m.near_condition || std::isinf(*m.near_condition)) continue;
        const double excess = *score.near_ulp / std::max(*m.near_condition, 1.0);
        figures_.push(out.excess, excess);
        const bool above = !(excess <= stability_factor);
        out.above_line += above;
        if (*m.near_condition < 1e3) {
            ++out.well_conditioned;
            out.well_conditioned_above += above;
        }
    }
    figures_.add_all(index, id);
}

void stability_accumulator::merge(const stability_accumulator& other) {
    merge_families(by_family, other.by_family, targets.size());
}

namespace {

stability_tally summarise(const stability_samples& s) {
    stability_tally tally;
    error_summary all_ulp;
    for (int b = 0; b < condition_bucket_count; ++b) {
        tally.buckets[b] = s.buckets[b];
        tally.buckets[b].near_root_ulp = s.near_ulp[b].statistics();
        all_ulp.merge(s.near_ulp[b]);
        tally.all.cases += s.buckets[b].cases;
        tally.all.misclassified += s.buckets[b].misclassified;
        tally.all.disagreements += s.buckets[b].disagreements;
        tally.all.conditioning_limited += s.buckets[b].conditioning_limited;
        tally.all.algorithmic += s.buckets[b].algorithmic;
        tally.all.by_design += s.buckets[b].by_design;
    }
    tally.all.near_root_ulp = all_ulp.statistics();
    tally.judged = s.excess.count;
    tally.above_line = s.above_line;
    tally.well_conditioned = s.well_conditioned;
    tally.well_conditioned_above = s.well_conditioned_above;
    tally.excess = s.excess.statistics();
    return tally;
}

}  // namespace

stability_totals stability_accumulator::finish(unsigned threads) const {
    stability_totals totals;
    std::tie(totals.overall, totals.by_family) =
        summarised(merged_over_families(by_family, targets.size(), threads), by_family, threads, summarise);
    return totals;
}

}  // namespace rayverify
