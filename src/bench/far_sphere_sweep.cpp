#include "bench/far_sphere_sweep.h"

#include <fmt/format.h>

#include <cmath>

#include "corpus/generators.h"

namespace rayverify::bench {

std::string distance_decade(double ratio) {
    const int decade = ratio < 1 ? 0 : static_cast<int>(std::floor(std::log10(ratio)));
    return fmt::format("d/r 1e{}..1e{}", decade, decade + 1);
}

std::vector<corpus_case> far_sphere_sweep(std::size_t count, std::uint64_t seed) {
    std::vector<corpus_case> cases = generate_family("far_sphere", count, seed);
    for (corpus_case& c : cases) {
        const vec3<double> f = c.geometry.origin - c.geometry.centre;
        c.family = distance_decade(std::sqrt(dot(f, f)) / c.geometry.radius);
    }
    return cases;
}

}  // namespace rayverify::bench
