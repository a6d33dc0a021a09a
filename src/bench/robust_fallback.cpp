#include "bench/robust_fallback.h"

#include <string_view>

#include "compare/judge.h"
#include "intersectors/robust.h"

namespace rayverify::bench {
namespace {

// Does the fast path alone answer variant `name` on this case?
template <class T>
bool fast_path_answers(std::string_view name, const ray_sphere<T>& s, ray_interval<T> interval) {
    const auto r = intersectors::robust_ray(s);
    const auto target = intersectors::robust_target(s);
    if (name == "robust") return robust_sphere::intersect_line_fast(r, target).has_value();
    if (name == "robust_nearest")
        return robust_sphere::nearest_hit_fast(r, target, interval.tmin, interval.tmax).has_value();
    return robust_sphere::any_hit_fast(r, target, interval.tmin, interval.tmax).has_value();
}

template <class T>
robust_fallback_row count(const std::string& family, std::string_view name, const std::vector<corpus_case>& cases) {
    constexpr precision prec = std::is_same_v<T, float> ? precision::binary32 : precision::binary64;
    robust_fallback_row row{family, std::string(name), precision_name(prec)};
    for (const corpus_case& c : cases) {
        if (validity<T>(c.geometry) != invalid_reason::none) continue;
        const t_range range = range_for(intersectors::robust_nearest_contract, c, prec);
        ++row.cases;
        if (!fast_path_answers<T>(name, rounded_to<T>(c.geometry),
                                  {static_cast<T>(range.lower), static_cast<T>(range.upper)}))
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
    return rows;
}

}  // namespace rayverify::bench
