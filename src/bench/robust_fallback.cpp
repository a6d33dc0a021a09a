#include "bench/robust_fallback.h"

#include <string_view>

#include "compare/judge.h"
#include "intersectors/robust.h"

namespace rayverify::bench {
namespace {

// Does variant `name`'s query settle this case with a solver of stage
// `Refine` (false: the static filter alone; true: with the double-word stage)?
template <bool Refine, class T>
bool settles(std::string_view name, const ray_sphere<T>& s, ray_interval<T> interval) {
    namespace rs = robust_sphere;
    using rs::ends;
    const rs::ray<T> ray = intersectors::robust_ray(s);  // the solver keeps references to both
    const rs::sphere<T> target = intersectors::robust_target(s);
    rs::detail::fast_solver<T, Refine> solver(ray, target);
    if (name == "robust" || name == "robust_bounded") {
        rs::line_roots<T> out;
        return name == "robust" ? rs::detail::query_line<rs::roots::correctly_rounded, T>(solver, out)
                                : rs::detail::query_line<rs::roots::bounded, T>(solver, out);
    }
    if (name == "robust_nearest" || name == "robust_bounded_nearest") {
        rs::ray_hit<T> out;
        return name == "robust_nearest"
                   ? rs::detail::query_nearest<ends::open, ends::open, rs::roots::correctly_rounded>(
                         solver, interval.tmin, interval.tmax, out)
                   : rs::detail::query_nearest<ends::open, ends::open, rs::roots::bounded>(solver, interval.tmin,
                                                                                          interval.tmax, out);
    }
    bool out = false;
    return rs::detail::query_any<ends::open, ends::open>(solver, interval.tmin, interval.tmax, out);
}

template <class T>
robust_fallback_row count(const std::string& family, std::string_view name, const std::vector<corpus_case>& cases) {
    constexpr precision prec = std::is_same_v<T, float> ? precision::binary32 : precision::binary64;
    robust_fallback_row row{family, std::string(name), precision_name(prec)};
    for (const corpus_case& c : cases) {
        if (validity<T>(c.geometry) != invalid_reason::none) continue;
        const t_range range = range_for(intersectors::robust_nearest_contract, c, prec);
        const ray_sphere<T> s = rounded_to<T>(c.geometry);
        const ray_interval<T> interval{static_cast<T>(range.lower), static_cast<T>(range.upper)};
        ++row.cases;
        if (settles<false>(name, s, interval)) continue;
        if (settles<true>(name, s, interval))
            ++row.refined;
        else
            ++row.exact;
    }
    return row;
}

// The segment query (closed ends, contact at the start) on segments_along
// the family's cases: left by the static filter, then by the double-word stage?
template <class T>
robust_fallback_row count_segments(const std::string& family, const std::vector<corpus_case>& cases) {
    namespace rs = robust_sphere;
    using rs::ends;
    constexpr precision prec = std::is_same_v<T, float> ? precision::binary32 : precision::binary64;
    robust_fallback_row row{family, robust_segment_name, precision_name(prec)};
    const auto settles = [](auto& solver) {
        rs::ray_hit<T> out;
        return rs::detail::query_segment<ends::closed, ends::closed, rs::start_inside::contact>(solver, out);
    };
    for (const segment_case<T>& c : segments_along<T>(cases)) {
        const rs::segment<T> g{{c.p0.x, c.p0.y, c.p0.z}, {c.p1.x, c.p1.y, c.p1.z}};
        const rs::sphere<T> target{{c.centre.x, c.centre.y, c.centre.z}, c.radius};
        ++row.cases;
        rs::detail::fast_solver<T, false, true> filter(g, target);
        if (settles(filter)) continue;
        rs::detail::fast_solver<T, true, true> refined(g, target);
        if (settles(refined))
            ++row.refined;
        else
            ++row.exact;
    }
    return row;
}

}  // namespace

std::vector<robust_fallback_row> robust_fallbacks(const std::map<std::string, std::vector<corpus_case>>& by_family) {
    std::vector<robust_fallback_row> rows;
    for (const auto& [family, cases] : by_family)
        for (const char* name : robust_variant_names) {
            rows.push_back(count<float>(family, name, cases));
            rows.push_back(count<double>(family, name, cases));
        }
    for (const auto& [family, cases] : by_family) {
        rows.push_back(count_segments<float>(family, cases));
        rows.push_back(count_segments<double>(family, cases));
    }
    return rows;
}

}  // namespace rayverify::bench
