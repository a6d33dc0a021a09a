#include "bench/long_double.h"

#include <string>

#include "bench/kernels.h"

namespace rayverify::bench {

std::vector<variant> long_double_variants() {
    std::vector<variant> out;
    for_each_kernel([&](std::string_view name, auto kernel) {
        if constexpr (has_long_double<decltype(kernel)>) {
            const variant* base = find_builtin_variant(name);
            variant v{base->name, base->citation, base->formula, base->promises, {}, {}};
            v.run_double = [kernel](const ray_sphere<double>& s) {
                const root_pair<long double> r = kernel(rounded_to<long double>(s));
                return root_pair<double>{r.count, static_cast<double>(r.t0), static_cast<double>(r.t1)};
            };
            if (takes_interval(base->promises))
                v.run_double_in = [kernel](const ray_sphere<double>& s, double tmin, double tmax) {
                    const root_pair<long double> r = kernel(rounded_to<long double>(s), static_cast<long double>(tmin),
                                                            static_cast<long double>(tmax));
                    return root_pair<double>{r.count, static_cast<double>(r.t0), static_cast<double>(r.t1)};
                };
            out.push_back(std::move(v));
        }
    });
    return out;
}

}  // namespace rayverify::bench
