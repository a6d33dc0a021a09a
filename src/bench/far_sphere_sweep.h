// The dense far-sphere sweep behind the Ray Tracing Gems ch.7 picture: the
// far_sphere generator's cases, each relabelled with the decade of its
// distance/radius ratio |o − c| / r as its family, so an audit tallies the
// sweep per decade.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/ray_sphere_case.h"

namespace rayverify::bench {

// "d/r 1e3..1e4" for 1000 ≤ ratio < 10000 (ratio ≥ 1).
std::string distance_decade(double ratio);

std::vector<corpus_case> far_sphere_sweep(std::size_t count, std::uint64_t seed);

}  // namespace rayverify::bench
