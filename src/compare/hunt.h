// The worst-case hunter: search for inputs on which one variant, in one
// precision, is as wrong as possible by the exact oracle's judgement.
//
// Random restarts from a family's cases (supplied by the caller, so this
// layer needs no generator), then local search: move one to three inputs by
// ±2^j ulps of the working precision (j uniform, so steps of every scale from
// one ulp to a doubling), keep the move when the oracle says the case is at
// least as bad. Each find is then shrunk (inputs zeroed, rounded to fewer
// significant bits, the scene translated to c = 0 and scaled to unit size;
// or, for start cases of the user's, moved back toward the start case) while
// it still fails the same way. Deterministic for a given seed and
// evaluation budget; a time budget only decides where it stops.
//
// Maxima found by search are lower bounds on the variant's true maximum.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compare/audit.h"
#include "compare/judge.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

enum class hunt_objective {
    ulp,             // maximise the nearest- or far-root ULP error over agreeing answers
    misclass,        // find disagreements (false miss or hit, tangent errors, wrong side, NaN, ...)
    scale_radius,    // maximise |t − t*|·|d|/r over agreeing answers: the error in units of the radius,
                     // which, unlike ULPs, does not explode as t* → 0
    scale_distance,  // maximise |t − t*|·|d|/|o − c| over agreeing answers
};
// The name --objective takes; nullopt for an unknown name.
std::optional<hunt_objective> hunt_objective_from_name(std::string_view name);
// The error figure an objective maximises (ulp, scale_radius, scale_distance; misclass: none).
bool maximises_error(hunt_objective o);
enum class hunt_strategy {
    search,  // random restarts + local search by ulp moves
    random,  // plain random sampling: every evaluation a fresh start case (the baseline)
};

std::optional<hunt_strategy> hunt_strategy_from_name(std::string_view name);
// The names of an objective and a strategy, as the options and the hunt file spell them.
std::string_view hunt_objective_name(hunt_objective o);
std::string_view hunt_strategy_name(hunt_strategy s);
// Every name --objective and --strategy take, in one place for the option's
// check and the shell completion.
std::vector<std::string> hunt_objective_names();
std::vector<std::string> hunt_strategy_names();

struct hunt_options {
    hunt_objective objective = hunt_objective::ulp;
    hunt_strategy strategy = hunt_strategy::search;
    std::uint64_t seed = 1;
    std::uint64_t max_evaluations = 0;  // search evaluations; 0: no limit (then max_seconds must be set)
    double max_seconds = 0;             // wall-clock budget of the search; 0: no limit
    std::size_t max_finds = 1;          // misclass: stop after this many disagreements
    // misclass: keep only disagreements whose cause is rounding (the judge's
    // case_score::cause is not by design: no clamp, contract semantics, unit
    // direction, tangent threshold or line-not-ray finds).
    bool rounding_only = false;
    // misclass: keep only disagreements with this cause (`--cause algorithmic`:
    // the ones a backward-stable formula avoids); nullopt keeps any.
    std::optional<disagreement_cause> only_cause;
    std::uint64_t patience = 400;       // evaluations without improvement before a restart
    bool shrink = true;
    // Shrink each find toward the start case it was searched from (the
    // user's own case, hunt --corpus): every input moved back to the start's
    // value, or as near it in ulps as keeps the failure, instead of toward
    // zeros and short numbers. The find is then the least change to that
    // case that fails.
    bool shrink_toward_start = false;
    // The cases are segments (hunt --corpus of segment cases, --family
    // segment_end): a candidate's ten numbers are p0, p1, c and r, its
    // direction field holding p1 (segment_search_inputs), so that every move
    // and every shrink moves an end point; each candidate is judged as the
    // segment between them (make_segment).
    bool segments = false;
    std::uint64_t shrink_evaluations = 4000;  // per find
    // Cases judged together: the random strategy's start cases, or the
    // search's candidates, all moved from the same current case and then
    // taken in order as if one by one (1: exactly one at a time). An
    // external program answers a batch in one exchange.
    std::size_t batch = 1;
    // Called every 512 search evaluations with the search so far (a live
    // progress line); the search does not depend on it.
    std::function<void(const struct hunt_progress&)> on_progress;
};

struct hunt_progress {
    std::uint64_t evaluations = 0;
    double seconds = 0;
    std::size_t finds = 0;     // misclass: disagreements found so far
    double best_error = 0;     // ulp: the largest error found so far (0 before the first)
};

// One case judged: what the hunter optimises.
struct hunt_evaluation {
    verdict_kind verdict = verdict_kind::invalid;
    std::optional<disagreement_cause> cause;  // of a disagreement
    std::string detail;
    // When the verdict is agree, else 0: max(near_ulp, far_ulp) for the ulp
    // objective, the scale error for the scale objectives (misclass: 0, no
    // figure is measured).
    double error = 0;
};

// A segment case's ten numbers as the hunter moves them: p0, p1 (in the
// direction field), c and r; and a hunt candidate of that form as the
// segment case it stands for, written into `c` (its id and source kept).
ray_sphere<double> segment_search_inputs(const corpus_case& segment);
void set_segment_candidate(corpus_case& c, const ray_sphere<double>& inputs);

hunt_evaluation evaluate_for_hunt(const audit_target& target, const ray_sphere<double>& input,
                                  hunt_objective objective = hunt_objective::ulp);
// The same for a case with an id (a target with recorded answers finds its answer by it).
hunt_evaluation evaluate_for_hunt(const audit_target& target, const corpus_case& c,
                                  hunt_objective objective = hunt_objective::ulp);

// Judges a batch of cases (ids unique in the batch), e.g. by asking an
// external program for their answers first; the default judges each with
// evaluate_for_hunt under the hunt's objective.
using hunt_judge = std::function<std::vector<hunt_evaluation>(std::span<const corpus_case> cases)>;

struct hunt_find {
    ray_sphere<double> found;   // as the search left it
    ray_sphere<double> shrunk;  // after shrinking (== found when nothing simpler fails the same way)
    hunt_evaluation found_eval, shrunk_eval;
    int found_bits = 0, shrunk_bits = 0;  // significant bits over the ten inputs
    // Shrunk toward the start case: the inputs that still differ from it, and
    // by how many steps of the precision in all.
    int inputs_changed = 0;
    std::uint64_t steps_from_start = 0;
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
    // ulp: the evaluations whose answer disagreed with the exact one (they have
    // no ULP error to maximise, but are findings all the same), and the first
    // of them as found.
    std::uint64_t disagreements = 0;
    std::optional<hunt_find> first_disagreement;
};

// Start case `index` (0, 1, ...), deterministic in its index.
using hunt_start = std::function<ray_sphere<double>(std::uint64_t index)>;

hunt_result hunt(const audit_target& target, const hunt_start& start, const hunt_options& options,
                 const hunt_judge& judge = {});

// A sharded hunt is N independent hunts: shard K (1 ≤ K ≤ N) starts from the
// start cases K − 1, K − 1 + N, … (the caller's hunt_start) and searches with
// this seed: `seed` itself when N = 1, else splitmix64's output function of
// seed + K·γ, a bijection in K, so that no two shards share a search seed.
std::uint64_t shard_search_seed(std::uint64_t seed, std::size_t shard_index, std::size_t shard_count);

// Significant bits of the ten inputs together (0 counts as 0 bits).
int significant_bits(const ray_sphere<double>& g);

}  // namespace rayverify
