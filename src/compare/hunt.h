// The worst-case hunter: search for inputs on which one variant, in one
// precision, is as wrong as possible by the exact oracle's judgement.
//
// Random restarts from a family's cases (supplied by the caller, so this
// layer needs no generator), then local search: move one to three inputs by
// ±2^j ulps of the working precision (j uniform, so steps of every scale from
// one ulp to a doubling), keep the move when the oracle says the case is at
// least as bad. Each find is then shrunk (inputs zeroed, rounded to fewer
// significant bits, the scene translated to c = 0 and scaled to unit size)
// while it still fails the same way. Deterministic for a given seed and
// evaluation budget; a time budget only decides where it stops.
//
// Maxima found by search are lower bounds on the variant's true maximum.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "compare/audit.h"
#include "compare/judge.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

enum class hunt_objective {
    ulp,       // maximise the nearest- or far-root ULP error over agreeing answers
    misclass,  // find disagreements (false miss or hit, tangent errors, wrong side, NaN, ...)
};
enum class hunt_strategy {
    search,  // random restarts + local search by ulp moves
    random,  // plain random sampling: every evaluation a fresh start case (the baseline)
};

const char* hunt_objective_name(hunt_objective o);
const char* hunt_strategy_name(hunt_strategy s);

struct hunt_options {
    hunt_objective objective = hunt_objective::ulp;
    hunt_strategy strategy = hunt_strategy::search;
    std::uint64_t seed = 1;
    std::uint64_t max_evaluations = 0;  // search evaluations; 0: no limit (then max_seconds must be set)
    double max_seconds = 0;             // wall-clock budget of the search; 0: no limit
    std::size_t max_finds = 1;          // misclass: stop after this many disagreements
    std::uint64_t patience = 400;       // evaluations without improvement before a restart
    bool shrink = true;
    std::uint64_t shrink_evaluations = 4000;  // per find
};

// One case judged: what the hunter optimises.
struct hunt_evaluation {
    verdict_kind verdict = verdict_kind::invalid;
    std::string detail;
    double error = 0;  // max(near_ulp, far_ulp) when the verdict is agree, else 0
};

hunt_evaluation evaluate_for_hunt(const audit_target& target, const ray_sphere<double>& input);

struct hunt_find {
    ray_sphere<double> found;   // as the search left it
    ray_sphere<double> shrunk;  // after shrinking (== found when nothing simpler fails the same way)
    hunt_evaluation found_eval, shrunk_eval;
    int found_bits = 0, shrunk_bits = 0;  // significant bits over the ten inputs
    std::uint64_t evaluation = 0;         // the search evaluation that found it (1-based)
    double seconds = 0;                   // search time when found
    std::uint64_t start_index = 0;        // the start case its search began from
};

struct hunt_result {
    // misclass: the disagreements in the order found; ulp: the single worst case.
    std::vector<hunt_find> finds;
    std::uint64_t evaluations = 0;  // search evaluations (shrinking not counted)
    std::uint64_t starts = 0;       // start cases drawn
    std::uint64_t shrink_evaluations = 0;
    double seconds = 0;  // search time
};

// Start case `index` (0, 1, ...), deterministic in its index.
using hunt_start = std::function<ray_sphere<double>(std::uint64_t index)>;

hunt_result hunt(const audit_target& target, const hunt_start& start, const hunt_options& options);

// A sharded hunt is N independent hunts: shard K (1 ≤ K ≤ N) starts from the
// start cases K − 1, K − 1 + N, … (the caller's hunt_start) and searches with
// this seed: `seed` itself when N = 1, else splitmix64's output function of
// seed + K·γ, a bijection in K, so that no two shards share a search seed.
std::uint64_t shard_search_seed(std::uint64_t seed, std::size_t shard_index, std::size_t shard_count);

// Significant bits of the ten inputs together (0 counts as 0 bits).
int significant_bits(const ray_sphere<double>& g);

}  // namespace rayverify
