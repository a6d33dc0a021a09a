#include "compare/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayverify {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// Double-double numbers (hi + lo, |lo| ≤ ulp(hi)/2): Dekker/Knuth error-free
// transformations, about 2^-104 relative error per operation.
struct dd {
    double hi = 0, lo = 0;
};

dd two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

dd quick_two_sum(double a, double b) {
    const double s = a + b;
    return {s, b - (s - a)};
}

dd two_prod(double a, double b) {
    const double p = a * b;
    return {p, std::fma(a, b, -p)};
}

dd operator+(dd a, dd b) {
    const dd s = two_sum(a.hi, b.hi);
    const dd t = two_sum(a.lo, b.lo);
    const dd u = quick_two_sum(s.hi, s.lo + t.hi);
    return quick_two_sum(u.hi, u.lo + t.lo);
}

dd operator-(dd a) { return {-a.hi, -a.lo}; }
dd operator-(dd a, dd b) { return a + (-b); }

dd operator*(dd a, dd b) {
    const dd p = two_prod(a.hi, b.hi);
    return quick_two_sum(p.hi, p.lo + (a.hi * b.lo + a.lo * b.hi));
}

dd operator/(dd a, dd b) {
    const double q1 = a.hi / b.hi;
    const dd r = a - b * dd{q1, 0};
    const double q2 = r.hi / b.hi;
    return quick_two_sum(q1, q2);
}

dd dd_sqrt(dd a) {
    if (a.hi <= 0) return {};
    const double x = std::sqrt(a.hi);
    const dd r = a - two_prod(x, x);
    return quick_two_sum(x, r.hi / (2 * x));
}

dd dd_abs(dd a) { return a.hi < 0 ? -a : a; }
double value(dd a) { return a.hi + a.lo; }

struct dd3 {
    dd x, y, z;
    dd operator[](int k) const { return k == 0 ? x : (k == 1 ? y : z); }
};

dd dot(const dd3& a, const dd3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The largest binary exponent among the values (for exact power-of-two scaling).
int max_exponent(std::initializer_list<double> values) {
    int e = std::numeric_limits<int>::min();
    for (double v : values)
        if (v != 0) e = std::max(e, std::ilogb(v));
    return e == std::numeric_limits<int>::min() ? 0 : e;
}

// κ of root t (scaled coordinates), see stability.h.
double condition_of(dd t, const dd3& f, const dd3& o, const dd3& d, const dd3& c, dd r, dd sqrt_discriminant) {
    double numerator = value(r * r);
    const double abs_t = std::fabs(value(t));
    for (int k = 0; k < 3; ++k) {
        const double p = std::fabs(value(f[k] + t * d[k]));
        numerator += p * (std::fabs(value(o[k])) + std::fabs(value(c[k])) + abs_t * std::fabs(value(d[k])));
    }
    return numerator / (value(sqrt_discriminant) * abs_t);
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
    const auto position = [&](double v) { return dd{std::ldexp(v, -position_exponent), 0}; };
    const auto direction = [&](double v) { return dd{std::ldexp(v, -direction_exponent), 0}; };
    const dd3 o{position(g.origin.x), position(g.origin.y), position(g.origin.z)};
    const dd3 c{position(g.centre.x), position(g.centre.y), position(g.centre.z)};
    const dd3 d{direction(g.direction.x), direction(g.direction.y), direction(g.direction.z)};
    const dd r = position(g.radius);

    // Quadratic coefficients a t² + 2b′t + C (f = o − c is exact in dd).
    const dd3 f{two_sum(o.x.hi, -c.x.hi), two_sum(o.y.hi, -c.y.hi), two_sum(o.z.hi, -c.z.hi)};
    const dd a = dot(d, d);
    const dd b_prime = dot(d, f);
    const dd C = dot(f, f) - r * r;
    const dd discriminant = b_prime * b_prime - a * C;

    m.discriminant_sign = exact.cls == line_class::tangent ? 0 : (exact.cls == line_class::miss ? -1 : 1);
    const double abs_discriminant = m.cls == line_class::tangent ? 0 : std::fabs(value(discriminant));
    m.tangency_distance = abs_discriminant / (value(b_prime * b_prime) + std::fabs(value(a * C)));

    // M = Σ |∂Δ′/∂x_i|·|x_i|.
    double sensitivity = value(a * r * r);
    for (int k = 0; k < 3; ++k) {
        const double along = std::fabs(value(b_prime * d[k] - a * f[k]));
        const double across = std::fabs(value(b_prime * f[k] - C * d[k]));
        sensitivity += along * (std::fabs(value(o[k])) + std::fabs(value(c[k]))) + across * std::fabs(value(d[k]));
    }
    sensitivity *= 2;
    const double u = std::ldexp(1.0, -significand_bits(prec));
    m.tangency_margin = sensitivity > 0 ? abs_discriminant / (u * sensitivity) : infinity;
    m.distance_ratio = std::sqrt(value(dot(f, f))) / value(r);

    if (m.cls == line_class::miss) return m;
    if (m.cls == line_class::tangent) {
        m.near_condition = m.far_condition = infinity;
        m.near_root = std::ldexp(value(-b_prime / a), position_exponent - direction_exponent);
        return m;
    }
    // Stable roots: q = −(b′ + sign(b′)√Δ′), roots q/a and C/q.
    const dd sqrt_discriminant = dd_sqrt(dd_abs(discriminant));
    const dd q = b_prime.hi >= 0 ? -(b_prime + sqrt_discriminant) : sqrt_discriminant - b_prime;
    dd t_near = q / a, t_far = C / q;
    if (value(t_near) > value(t_far)) std::swap(t_near, t_far);
    m.near_root = std::ldexp(value(t_near), position_exponent - direction_exponent);
    const bool resolved = value(discriminant) > 0;  // dd resolves Δ′ (else κ is beyond its reach)
    const auto kappa = [&](dd t, int sign) {
        if (sign == 0 || !resolved) return infinity;
        return condition_of(t, f, o, d, c, r, sqrt_discriminant);
    };
    m.near_condition = kappa(t_near, exact.near_root.sign);
    m.far_condition = kappa(t_far, exact.far_root.sign);
    return m;
}

bool is_misclassification(verdict_kind k) {
    switch (k) {
        case verdict_kind::false_miss:
        case verdict_kind::false_hit:
        case verdict_kind::tangent_split:
        case verdict_kind::tangent_missed:
        case verdict_kind::false_tangent:
            return true;
        default:
            return false;
    }
}

const char* disagreement_cause_name(disagreement_cause c) {
    return c == disagreement_cause::conditioning_limited ? "conditioning_limited" : "algorithmic";
}

std::optional<disagreement_cause> classify_disagreement(verdict_kind k, const stability_measures& s, precision prec) {
    if (!is_disagreement(k) || !s.valid) return std::nullopt;
    const bool ambiguous_class = s.tangency_margin <= conditioning_gamma;
    if (is_misclassification(k))
        return ambiguous_class ? disagreement_cause::conditioning_limited : disagreement_cause::algorithmic;
    if (k == verdict_kind::wrong_root || k == verdict_kind::wrong_side) {
        const double u = std::ldexp(1.0, -significand_bits(prec));
        const bool ambiguous_root = s.near_condition && conditioning_gamma * u * *s.near_condition >= 1;
        return ambiguous_class || ambiguous_root ? disagreement_cause::conditioning_limited
                                                 : disagreement_cause::algorithmic;
    }
    return disagreement_cause::algorithmic;
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

case_stability assess_case(const audited_case& c, std::span<const audit_target> targets) {
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
    result.causes.reserve(targets.size());
    for (std::size_t t = 0; t < targets.size(); ++t)
        result.causes.push_back(
            classify_disagreement(c.outcomes[t].score.verdict, result.at(targets[t].prec), targets[t].prec));
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
        near_ulp[b].merge(other.near_ulp[b]);
    }
    excess.merge(other.excess);
    above_line += other.above_line;
    well_conditioned += other.well_conditioned;
    well_conditioned_above += other.well_conditioned_above;
}

stability_accumulator::stability_accumulator(std::vector<audit_target> t)
    : targets(std::move(t)), overall(targets.size()) {}

void stability_accumulator::add(const audited_case& c, const case_stability& s, std::size_t index) {
    auto& family_samples = by_family[family_key(*c.source)];
    family_samples.resize(targets.size());
    const std::string& id = c.source->id;
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const case_score& score = c.outcomes[t].score;
        if (score.verdict == verdict_kind::invalid || score.verdict == verdict_kind::contract_violation) continue;
        const stability_measures& m = s.at(targets[t].prec);
        const int bucket = condition_bucket(m);
        for (stability_samples* out : {&overall[t], &family_samples[t]}) {
            bucket_tally& b = out->buckets[bucket];
            ++b.cases;
            if (is_misclassification(score.verdict)) ++b.misclassified;
            if (is_disagreement(score.verdict)) ++b.disagreements;
            if (s.causes[t] == disagreement_cause::conditioning_limited) ++b.conditioning_limited;
            if (s.causes[t] == disagreement_cause::algorithmic) ++b.algorithmic;
            if (score.verdict != verdict_kind::agree || !score.near_ulp) continue;
            out->near_ulp[bucket].add(*score.near_ulp, index, id);
            if (!m.near_condition || std::isinf(*m.near_condition)) continue;
            const double excess = *score.near_ulp / std::max(*m.near_condition, 1.0);
            out->excess.add(excess, index, id);
            const bool above = !(excess <= stability_factor);
            out->above_line += above;
            if (*m.near_condition < 1e3) {
                ++out->well_conditioned;
                out->well_conditioned_above += above;
            }
        }
    }
}

void stability_accumulator::merge(const stability_accumulator& other) {
    merge_per_target(overall, by_family, other.overall, other.by_family, targets.size());
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

stability_totals stability_accumulator::finish() const {
    stability_totals totals;
    for (const stability_samples& s : overall) totals.overall.push_back(summarise(s));
    for (const auto& [family, per_target] : by_family) {
        auto& out = totals.by_family[family];
        for (const stability_samples& s : per_target) out.push_back(summarise(s));
    }
    return totals;
}

}  // namespace rayverify
