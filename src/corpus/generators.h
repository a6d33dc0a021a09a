// Deterministic case generators: named families of ray–sphere cases, each
// built to stress one thing, some with an exact guarantee about the line's
// class (tangent, two roots) that the oracle can confirm.
//
// Determinism: a case depends only on (family, seed, index) — never on count,
// the platform or the standard library's distributions. Every random value
// comes from std::mt19937_64 raw outputs (fully specified by the standard)
// converted by our own code; only +, −, ×, ÷, √ and ldexp (all correctly
// rounded or exact) shape output bits, never sin/cos/exp/log/pow.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "core/ray_sphere_case.h"

namespace rayverify {

// What a family guarantees about the exact class of the line o + t·d
// (in binary64, for the inputs exactly as generated).
enum class class_claim { any, miss, tangent, two_hit };

const char* class_claim_name(class_claim c);

struct family_info {
    std::string_view name;
    std::string_view description;  // what it stresses and how it is built
    class_claim claim;
    bool unit_direction;  // every direction is normalised in double (|d·d − 1| ≤ 2^-51)
    bool float_exact = false;  // every input is exactly a float: float variants see the case itself
    bool interval = false;     // every case has an interval (tmin, tmax): the range-end families
    bool segment = false;      // every case is a segment (p0, p1; corpus_case::segment_end): its interval is [0, 1]
    int version = 1;           // bumped whenever the family's output for a (seed, index) changes
};

// All families, in a fixed order.
std::span<const family_info> generator_families();

// nullptr when no family has that name.
const family_info* find_generator_family(std::string_view name);

// `count` cases of `family`. Case i has id "<family>-<seed>-<i as 6 digits>",
// source "generated", an interval where its family_info says so (the
// range-end families), and is the same whatever `count` is.
// Throws input_error (field "family") for an unknown family.
std::vector<corpus_case> generate_family(std::string_view family, std::size_t count,
                                         std::uint64_t seed);

// Case `index` of generate_family(family, n, seed) for any n > index, alone.
corpus_case generate_case(std::string_view family, std::uint64_t seed, std::size_t index);

// Cases `indices` of generate_family(family, n, seed), appended to `out` in
// that order: the cases generate_case makes, several at a time (the random
// engines of four cases seeded side by side).
void append_generated_cases(std::string_view family, std::uint64_t seed, std::span<const std::size_t> indices,
                            std::vector<corpus_case>& out);

}  // namespace rayverify
