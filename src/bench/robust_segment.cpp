// robust_sphere.h's segment query on each family's rays cast as segments:
// the cases (segments_along) and its timing against a naive double segment
// cast (robust_fallback.h).
#include <cmath>
#include <limits>

#include "bench/robust_fallback.h"
#include "core/intersection.h"
#include "intersectors/naive.h"
#include "intersectors/robust.h"

namespace rayverify::bench {

template <class T>
std::vector<segment_case<T>> segments_along(const std::vector<corpus_case>& cases) {
    std::vector<segment_case<T>> out;
    for (const corpus_case& c : cases) {
        if (c.is_segment() || validity<T>(c.geometry) != invalid_reason::none) continue;
        const ray_sphere<double>& g = c.geometry;
        const double length = static_cast<double>(segment_length(rounded_to<T>(g)));
        const vec3<double> end = g.origin + length * g.direction;
        // p1 within T's range before it is converted (a conversion out of range is undefined).
        const double largest = static_cast<double>(std::numeric_limits<T>::max());
        if (!(std::fabs(end.x) <= largest && std::fabs(end.y) <= largest && std::fabs(end.z) <= largest)) continue;
        const segment_case<T> s{vec3_cast<T>(g.origin), vec3_cast<T>(end), vec3_cast<T>(g.centre),
                                static_cast<T>(g.radius)};
        if (s.p1 != s.p0) out.push_back(s);
    }
    return out;
}

template std::vector<segment_case<float>> segments_along(const std::vector<corpus_case>&);
template std::vector<segment_case<double>> segments_along(const std::vector<corpus_case>&);

namespace {

// The nearest contact f ∈ [0, 1] of robust_sphere.h's segment query, or −1.
template <class T>
inline double robust_fraction(const segment_case<T>& c) {
    namespace rs = robust_sphere;
    const rs::segment<T> g{{c.p0.x, c.p0.y, c.p0.z}, {c.p1.x, c.p1.y, c.p1.z}};
    const rs::ray_hit<T> h = rs::segment_hit(g, rs::sphere<T>{{c.centre.x, c.centre.y, c.centre.z}, c.radius});
    return h.found ? double(h.t) : -1;
}

// The textbook segment cast in double: the naive quadratic on d = RN(p1 − p0),
// its first root in [0, 1], or −1.
inline double naive_fraction(const segment_case<double>& c) {
    const root_pair<double> r = intersectors::naive(ray_sphere<double>{c.p0, c.p1 - c.p0, c.centre, c.radius});
    if (r.count > 0 && r.t0 >= 0 && r.t0 <= 1) return r.t0;
    if (r.count > 1 && r.t1 >= 0 && r.t1 <= 1) return r.t1;
    return -1;
}

template <class T, class Query>
[[gnu::flatten]] double one_pass(const std::vector<segment_case<T>>& segments, Query query) {
    double sum = 0;
    for (const segment_case<T>& s : segments) sum += query(s);
    return sum;
}

}  // namespace

std::vector<timing_row> time_segment_queries(const std::map<std::string, std::vector<corpus_case>>& by_family,
                                             const timing_options& options) {
    std::vector<timing_row> rows;
    for (const char* family : robust_target_families) {
        const auto found = by_family.find(family);
        if (found == by_family.end()) continue;
        const std::vector<segment_case<float>> in_float = segments_along<float>(found->second);
        const std::vector<segment_case<double>> in_double = segments_along<double>(found->second);
        const auto row = [&](const char* name, const char* prec, std::size_t cases) {
            timing_row r;
            r.variant = name;
            r.precision = prec;
            r.family = family;
            r.cases = cases;
            return r;
        };
        rows.push_back(time_pass(row(naive_segment_name, "double", in_double.size()),
                                 [&] { return one_pass(in_double, naive_fraction); }, options));
        if (times_precision(options, "float"))
            rows.push_back(time_pass(row(robust_segment_name, "float", in_float.size()),
                                     [&] { return one_pass(in_float, robust_fraction<float>); }, options));
        if (times_precision(options, "double"))
            rows.push_back(time_pass(row(robust_segment_name, "double", in_double.size()),
                                     [&] { return one_pass(in_double, robust_fraction<double>); }, options));
    }
    return rows;
}

}  // namespace rayverify::bench
