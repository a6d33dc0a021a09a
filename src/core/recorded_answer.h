// Answers computed outside rayverify (a results file, an external program):
// what an intersector returned for each case, keyed by the case's id, so that
// the audit finds a case's answer through the case itself, never through its
// geometry. The judge (compare/judge.h) takes a recorded answer exactly where
// it would run a built-in variant; the readers are in corpus/exchange.h.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "core/vec3.h"

namespace rayverify {

// One case's answer, widened to double (a float answer is exact in double).
// The optional outputs beside t are what an engine may hand over: a
// conservative interval around each t, its own hit point, and the normal.
struct recorded_answer {
    root_pair<double> roots;
    // Whether t0 and t1 were given. An absent one is NaN here and never
    // judged: the reader takes count 1 without t1 as a tangent's root written
    // once (t1 = t0), and the audit refuses an answer whose contract needs a
    // value it left out (corpus/exchange.h, check_recorded_values).
    bool t0_given = true, t1_given = true;
    std::optional<std::array<double, 2>> t0_bounds, t1_bounds;  // [lo, hi]
    std::optional<vec3<double>> hit_point;
    std::optional<vec3<double>> normal;
    std::size_t line = 0;  // where it was read (a file's line, or an answer's position)
};

// Every answer of one results file or one batch, in one precision.
struct answer_book {
    std::string source;  // the file (or command) the answers came from, for messages
    precision prec = precision::binary64;
    std::unordered_map<std::string, recorded_answer> by_id;

    // nullptr when no answer has that id.
    const recorded_answer* find(const std::string& id) const {
        const auto at = by_id.find(id);
        return at == by_id.end() ? nullptr : &at->second;
    }
};

}  // namespace rayverify
