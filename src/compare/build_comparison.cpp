#include "compare/build_comparison.h"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace rayverify {
namespace {

// The same double, bit for bit (so -0 differs from +0), any NaN the same as
// any other: a NaN's sign and payload are no answer (clang -O0 and gcc -O2
// give the NaN of 0/0 opposite signs).
bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) || (a != a && b != b);
}

template <class T>
bool same_optional(const std::optional<T>& a, const std::optional<T>& b, bool (*same)(const T&, const T&)) {
    return a.has_value() == b.has_value() && (!a || same(*a, *b));
}

bool same_vector(const vec3<double>& a, const vec3<double>& b) {
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

bool same_bounds(const std::array<std::array<double, 2>, 2>& a, const std::array<std::array<double, 2>, 2>& b) {
    for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j)
            if (!same_bits(a[i][j], b[i][j])) return false;
    return true;
}

bool same_int(const int& a, const int& b) { return a == b; }

// The larger of a judged answer's root ULP errors, when it has one.
std::optional<double> root_error(const case_score& s) {
    if (s.near_ulp && s.far_ulp) return std::max(*s.near_ulp, *s.far_ulp);
    return s.near_ulp ? s.near_ulp : s.far_ulp;
}

}  // namespace

bool same_answer(const variant_output& a, const variant_output& b) {
    if (a.roots.count != b.roots.count) return false;
    if (a.roots.count >= 1 && !same_bits(a.roots.t0, b.roots.t0)) return false;
    if (a.roots.count >= 2 && !same_bits(a.roots.t1, b.roots.t1)) return false;
    return same_optional(a.hit_root, b.hit_root, same_int) && same_optional(a.hit_point, b.hit_point, same_vector) &&
           same_optional(a.t_bounds, b.t_bounds, same_bounds) &&
           same_optional(a.point_error, b.point_error, same_vector) && same_optional(a.normal, b.normal, same_vector) &&
           a.nan_seen == b.nan_seen;
}

int flip_severity(verdict_kind reference, verdict_kind build) {
    if (is_misclassification(build)) return 0;
    if (is_disagreement(build)) return 1;
    if (is_disagreement(reference)) return 2;
    return 3;
}

std::vector<flip_count> flips_worst_first(std::vector<flip_count> flips) {
    std::stable_sort(flips.begin(), flips.end(), [](const flip_count& a, const flip_count& b) {
        const int sa = flip_severity(a.first.first, a.first.second), sb = flip_severity(b.first.first, b.first.second);
        return sa != sb ? sa < sb : a.second > b.second;
    });
    return flips;
}

std::vector<build_flip> build_difference::worst(std::size_t count) const {
    std::vector<build_flip> out;
    for (const auto& [kinds, cases] : flips_worst_first({flips.begin(), flips.end()})) {
        if (out.size() == count) break;
        const auto first = first_flips.find(kinds);
        if (first != first_flips.end()) out.push_back(first->second);
    }
    return out;
}

build_comparison::build_comparison(std::vector<std::pair<std::size_t, std::size_t>> pairs, std::size_t kept_changes)
    : kept_changes_(kept_changes) {
    for (const auto& [build, reference] : pairs) {
        build_difference d;
        d.target = build;
        d.reference = reference;
        differences_.push_back(std::move(d));
    }
}

void build_comparison::add(const audited_case& audited, std::size_t index) {
    for (build_difference& d : differences_) {
        const target_outcome& built = audited.outcomes[d.target];
        const target_outcome& reference = audited.outcomes[d.reference];
        if (!is_scored(built.score.verdict) || !is_scored(reference.score.verdict)) {
            if (built.score.verdict != reference.score.verdict)
                ++d.flips[{reference.score.verdict, built.score.verdict}];
            continue;
        }
        ++d.cases;
        const bool changed = !same_answer(built.output, reference.output);
        if (changed) {
            ++d.answers_changed;
            if (d.changes.size() < kept_changes_)
                d.changes.push_back({*audited.source, built.output, reference.score.verdict, built.score.verdict});
        }
        if (built.score.verdict != reference.score.verdict) {
            const std::pair<verdict_kind, verdict_kind> kinds{reference.score.verdict, built.score.verdict};
            ++d.flips[kinds];
            if (!d.first_flips.contains(kinds))
                d.first_flips.emplace(kinds, build_flip{index, *audited.source, kinds.first, kinds.second,
                                                        reference.output, built.output,
                                                        built.score.detail.empty() ? reference.score.detail
                                                                                   : built.score.detail});
        } else if (changed && built.score.verdict == verdict_kind::agree) {
            const std::optional<double> mine = root_error(built.score), theirs = root_error(reference.score);
            if (mine && theirs) {
                if (*mine < *theirs) ++d.better;
                if (*mine > *theirs) ++d.worse;
            }
        }
    }
}

}  // namespace rayverify
