#include "compare/hunt.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include "core/case_in_progress.h"
#include "core/float_bits.h"
#include "core/hash.h"
#include "core/name_table.h"

namespace rayverify {

namespace {

constexpr name_table<hunt_objective, 4> objective_names{{{hunt_objective::ulp, "ulp"},
                                                        {hunt_objective::misclass, "misclass"},
                                                        {hunt_objective::scale_radius, "scale_radius"},
                                                        {hunt_objective::scale_distance, "scale_distance"}}};
constexpr name_table<hunt_strategy, 2> strategy_names{{{hunt_strategy::search, "search"}, {hunt_strategy::random, "random"}}};

}  // namespace

std::vector<std::string> hunt_objective_names() { return names_in(objective_names); }
std::vector<std::string> hunt_strategy_names() { return names_in(strategy_names); }

std::optional<hunt_strategy> hunt_strategy_from_name(std::string_view name) { return value_in(strategy_names, name); }
std::optional<hunt_objective> hunt_objective_from_name(std::string_view name) { return value_in(objective_names, name); }

std::string_view hunt_objective_name(hunt_objective o) { return name_in(objective_names, o); }
std::string_view hunt_strategy_name(hunt_strategy s) { return name_in(strategy_names, s); }

bool maximises_error(hunt_objective o) { return o != hunt_objective::misclass; }

namespace {

constexpr std::uint64_t golden_gamma = 0x9e3779b97f4a7c15ULL;

// splitmix64: the hunter's own generator (no std distributions).
class hunt_random {
public:
    explicit hunt_random(std::uint64_t seed) : state_(seed ^ 0x5eed0fa11b0c5e1fULL) {}
    std::uint64_t next() { return splitmix64_finalise(state_ += golden_gamma); }
    // Uniform on [0, n) (n small: the bias of the modulo is below 2^-50).
    std::uint64_t below(std::uint64_t n) { return next() % n; }
    bool coin() { return (next() >> 63) != 0; }

private:
    std::uint64_t state_;
};

double& input_at(ray_sphere<double>& g, int i) {
    switch (i) {
        case 0: return g.origin.x;
        case 1: return g.origin.y;
        case 2: return g.origin.z;
        case 3: return g.direction.x;
        case 4: return g.direction.y;
        case 5: return g.direction.z;
        case 6: return g.centre.x;
        case 7: return g.centre.y;
        case 8: return g.centre.z;
        default: return g.radius;
    }
}
double input_at(const ray_sphere<double>& g, int i) { return input_at(const_cast<ray_sphere<double>&>(g), i); }

double step_in(precision p, double x, std::int64_t steps) {
    return with_precision(p, [&]<class T>(std::type_identity<T>) {
        return static_cast<double>(step_by<T>(static_cast<T>(x), steps));
    });
}

// x rounded to the precision. The volatile store is needed: GCC 12 at -O2
// (SLP vectorizer) drops a double → float → double round trip on some lanes
// when a whole ray_sphere is converted at once.
double round_to(precision p, double x) {
    if (p == precision::binary64) return x;
    const volatile float rounded = static_cast<float>(x);
    return static_cast<double>(rounded);
}

ray_sphere<double> rounded_in(precision p, const ray_sphere<double>& g) {
    ray_sphere<double> out = g;
    for (int i = 0; i < 10; ++i) input_at(out, i) = round_to(p, input_at(g, i));
    return out;
}

// x with only its `bits` leading significant bits (round to nearest, ties to even).
double keep_bits(double x, int bits) {
    if (x == 0 || !std::isfinite(x)) return x;
    int e = 0;
    const double m = std::frexp(x, &e);                      // x = m·2^e, 0.5 ≤ |m| < 1
    return std::ldexp(std::nearbyint(std::ldexp(m, bits)), e - bits);  // exact: bits ≤ 53
}

int significand_bits_in(double x) {
    if (x == 0 || !std::isfinite(x)) return 0;
    int e = 0;
    double m = std::fabs(std::frexp(x, &e));
    int bits = 0;
    while (m != 0) {
        m = m * 2;
        m -= std::floor(m);
        ++bits;
    }
    return bits;
}

// How far the line is from tangency, relative: |dist² − r²| / r², with dist the
// distance of the line from c, in long double. Only a guide towards the
// boundary where classes flip; the oracle decides every verdict.
long double tangency_gap(const ray_sphere<double>& g) {
    using L = long double;
    const L fx = L(g.origin.x) - g.centre.x, fy = L(g.origin.y) - g.centre.y, fz = L(g.origin.z) - g.centre.z;
    const L dx = g.direction.x, dy = g.direction.y, dz = g.direction.z;
    const L a = dx * dx + dy * dy + dz * dz;
    const L b = fx * dx + fy * dy + fz * dz;
    const L s = b / a;
    const L px = fx - s * dx, py = fy - s * dy, pz = fz - s * dz;
    const L r2 = L(g.radius) * g.radius;
    const L gap = std::fabs(px * px + py * py + pz * pz - r2);
    return r2 > 0 ? gap / r2 : gap;
}

// The hunter's score of a case: larger is worse for the variant. A
// disagreement outranks everything under misclass; under ulp only agreeing
// answers count (their error), anything else is −1. The search judges with
// the error bracketed (evaluate_bracketed), so a score is known to lie in
// [lower, upper]; lower == upper once exact.
struct fitness {
    int tier = 0;
    long double lower = 0, upper = 0;
};

// compare(a, b) when the bounds decide it: empty where the brackets overlap
// and are not both exact.
uncertain_comparison compare_fitness(const fitness& a, const fitness& b) {
    if (a.tier != b.tier) return compare(a.tier, b.tier);
    if (a.lower > b.upper) return comparison::larger;
    if (a.upper < b.lower) return comparison::smaller;
    if (a.lower == a.upper && b.lower == b.upper) return comparison::equal;
    return std::nullopt;
}

// A disagreement the hunt keeps: any, or with rounding_only one whose cause
// is rounding, or with only_cause one of that cause.
bool kept_disagreement(const hunt_evaluation& e, const hunt_options& options) {
    if (!is_disagreement(e.verdict)) return false;
    if (options.rounding_only && e.cause && is_by_design(*e.cause)) return false;
    return !options.only_cause || e.cause == options.only_cause;
}

// `error`: bounds on e.error (exact under misclass and the scale objectives).
fitness fitness_of(const hunt_options& options, const hunt_evaluation& e, const figure_bracket& error,
                   const ray_sphere<double>& g) {
    if (!is_scored(e.verdict)) return {-1, 0, 0};
    if (options.objective == hunt_objective::misclass) {
        if (kept_disagreement(e, options)) return {1, 0, 0};
        const long double gap = tangency_gap(g);
        const long double closeness = gap > 0 ? 1 / gap : std::numeric_limits<long double>::max();
        return {0, closeness, closeness};
    }
    if (e.verdict != verdict_kind::agree) return {-1, 0, 0};
    return {0, error.lower, error.upper};
}

// The figures the hunt judges a case by: the objective's own error, exact or
// (ulp) bracketed from the oracle's enclosures; misclass, none.
figure_request figures_for(hunt_objective objective, bool bracketed) {
    figure_request wanted = figure_request::verdict_only();
    switch (objective) {
        case hunt_objective::misclass: break;
        case hunt_objective::ulp:
            wanted.roots = bracketed ? figure_request::root_errors::bracketed : figure_request::root_errors::exact;
            break;
        case hunt_objective::scale_radius:
        case hunt_objective::scale_distance: wanted.scale_errors = true; break;
    }
    return wanted;
}

// evaluate_for_hunt's judgement with, when `bracketed`, the ulp objective's
// error only bracketed (it ranks almost every case; the hunter settles it
// where a comparison or a find needs it exactly): the evaluation, its
// error set when the bracket is exact, and the bracket.
std::pair<hunt_evaluation, figure_bracket> evaluate_bracketed(const audit_target& target, const corpus_case& c,
                                                              hunt_objective objective, bool bracketed) {
    const target_outcome outcome =
        judge_target(target, c, solve_case(c, target.prec), given_answer{}, figures_for(objective, bracketed));
    const case_score& score = outcome.score;
    hunt_evaluation e{score.verdict, score.cause, score.detail};
    if (score.verdict != verdict_kind::agree) return {std::move(e), {}};
    std::optional<double> error;
    switch (objective) {
        case hunt_objective::misclass: break;
        case hunt_objective::ulp:
            if (score.root_ulp_bracket && !score.root_ulp_bracket->exact())
                return {std::move(e), *score.root_ulp_bracket};
            error = score.root_ulp_bracket ? score.root_ulp_bracket->lower
                                           : std::max(score.near_ulp.value_or(0), score.far_ulp.value_or(0));
            break;
        case hunt_objective::scale_radius: error = score.scale_error_radius; break;
        case hunt_objective::scale_distance: error = score.scale_error_distance; break;
    }
    e.error = error.value_or(0);
    const figure_bracket exact_error{e.error, e.error};
    return {std::move(e), exact_error};
}

// Does `e` fail the way `original` did? Same disagreement kind; for an ULP find,
// an agreeing answer with at least half the error.
bool same_failure(const hunt_options& options, const hunt_evaluation& original, const hunt_evaluation& e) {
    if (options.objective == hunt_objective::misclass)
        return e.verdict == original.verdict && e.cause == original.cause && kept_disagreement(e, options);
    return e.verdict == verdict_kind::agree && e.error >= original.error / 2 && e.error > 0;
}

// A case the search judged: its evaluation, bounds on its error (the
// search judges with the ulp objective's error bracketed), and its score.
// `number` names it ("hunt-evaluation-N") for a plugin that crashes on it.
struct judged_case {
    ray_sphere<double> geometry;
    hunt_evaluation eval;  // eval.error is the error once error.exact()
    figure_bracket error;
    fitness fit;
    std::uint64_t number = 0;
};

class hunter {
public:
    hunter(const audit_target& target, const hunt_start& start, const hunt_options& options, const hunt_judge& judge)
        : target_(target), start_(start), options_(options), judge_(judge), random_(options.seed),
          began_(std::chrono::steady_clock::now()) {}

    hunt_result run() {
        best_.reset();
        while (!exhausted()) {
            if (options_.strategy == hunt_strategy::random) {
                // A batch of fresh start cases.
                moved_.resize(batch_size());
                const std::uint64_t first = result_.starts;
                for (auto& g : moved_) g = rounded_in(target_.prec, start_(result_.starts++));
                std::vector<judged_case>& judged = judge_batch(moved_, "evaluation", result_.evaluations, first);
                for (std::size_t k = 0; k < judged.size() && !done(); ++k) {
                    count_evaluation();
                    start_index_ = first + k;
                    note(judged[k], start_index_);
                }
                continue;
            }
            const std::uint64_t index = result_.starts++;
            start_index_ = index;
            moved_.assign(1, rounded_in(target_.prec, start_(index)));
            judged_case current = std::move(judge_batch(moved_, "evaluation", result_.evaluations, index).front());
            count_evaluation();
            note(current, index);
            if (done()) continue;

            std::uint64_t stale = 0;
            while (!exhausted() && !done() && stale < options_.patience && current.fit.tier < 1) {
                // Candidates all moved from the current case, then taken in order as if one at a time.
                moved_.resize(batch_size());
                for (auto& g : moved_) g = mutate(current.geometry);
                std::vector<judged_case>& candidates = judge_batch(moved_, "evaluation", result_.evaluations, index);
                for (std::size_t k = 0; k < candidates.size() && !done(); ++k) {
                    count_evaluation();
                    judged_case& candidate = candidates[k];
                    note(candidate, index);
                    const comparison order = rank(candidate, current);
                    stale = order == comparison::larger ? 0 : stale + 1;
                    if (order != comparison::smaller) current = std::move(candidate);
                }
            }
        }
        result_.seconds = elapsed();
        if (maximises_error(options_.objective) && best_) result_.finds.push_back(*best_);
        if (options_.shrink)
            for (hunt_find& f : result_.finds) {
                if (options_.shrink_toward_start)
                    shrink_toward_start(f);
                else
                    shrink(f);
            }
        return result_;
    }

private:
    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count();
    }
    // Out of budget. The clock is read every 16th evaluation (reading it
    // took a tenth of a fast evaluation); a time budget only decides where
    // the search stops.
    bool exhausted() const {
        if (done()) return true;
        if (options_.max_evaluations > 0 && result_.evaluations >= options_.max_evaluations) return true;
        if (options_.max_seconds <= 0 || out_of_time_) return out_of_time_;
        if (result_.evaluations - clock_read_at_ < 16 && result_.evaluations > 0) return false;
        clock_read_at_ = result_.evaluations;
        out_of_time_ = elapsed() >= options_.max_seconds;
        return out_of_time_;
    }
    bool done() const {
        return options_.objective == hunt_objective::misclass && result_.finds.size() >= options_.max_finds;
    }

    // Counts one evaluation; every 512th, the progress so far goes to the caller.
    void count_evaluation() {
        ++result_.evaluations;
        if (options_.on_progress && result_.evaluations % 512 == 0)
            options_.on_progress({result_.evaluations, elapsed(), result_.finds.size(),
                                  best_ ? best_->found_eval.error : 0.0});
    }

    // The cases a batch may hold: the batch size, within the evaluation budget.
    std::size_t batch_size() const {
        std::uint64_t n = std::max<std::size_t>(1, options_.batch);
        if (options_.max_evaluations > 0) n = std::min(n, options_.max_evaluations - result_.evaluations);
        return static_cast<std::size_t>(std::max<std::uint64_t>(n, 1));
    }

    // Case number N of `stage` ("hunt-evaluation-N"), searched from start
    // case `start`, written into `c`, whose strings keep their storage from
    // batch to batch (formatting them was a tenth of a fast evaluation).
    void name_case(corpus_case& c, const ray_sphere<double>& g, const char* stage, std::uint64_t number,
                   std::uint64_t start) {
        char digits[24];
        c.id.assign("hunt-").append(stage).append("-").append(digits, std::to_chars(digits, digits + 24, number).ptr);
        if (!source_start_ || *source_start_ != start) {
            source_ = fmt::format("hunt, searching from start case {}", start);
            source_start_ = start;
        }
        c.source.assign(source_);
        if (options_.segments)
            set_segment_candidate(c, g);
        else
            c.geometry = g;
    }

    // Judges cases numbered after `before` in `stage`, searched from start
    // case `start`: with the ulp objective's error bracketed unless `exact`
    // (an external judge's errors are always exact). A plugin that crashes
    // or hangs names the case it was given (core/case_in_progress.h); a batch
    // judge names its batch. The judged cases live in a member, reused batch
    // after batch, until the next batch.
    std::vector<judged_case>& judge_batch(const std::vector<ray_sphere<double>>& gs, const char* stage,
                                          std::uint64_t before, std::uint64_t start, bool exact = false) {
        cases_.resize(gs.size());
        for (std::size_t k = 0; k < gs.size(); ++k) name_case(cases_[k], gs[k], stage, before + k + 1, start);
        std::vector<judged_case>& judged = judged_;
        judged.resize(gs.size());
        if (judge_) {
            std::vector<hunt_evaluation> evals = judge_(cases_);
            for (std::size_t k = 0; k < gs.size(); ++k) {
                const figure_bracket exact_error{evals[k].error, evals[k].error};
                score(judged[k], gs[k], std::move(evals[k]), exact_error, before + k + 1);
            }
            return judged;
        }
        for (std::size_t k = 0; k < gs.size(); ++k) {
            const case_in_progress announced(cases_[k]);
            auto [eval, error] = evaluate_bracketed(target_, cases_[k], options_.objective, !exact);
            score(judged[k], gs[k], std::move(eval), error, before + k + 1);
        }
        return judged;
    }

    // Fills `j` in place (a judged case built and copied was a tenth of the batch's own time).
    void score(judged_case& j, const ray_sphere<double>& g, hunt_evaluation&& e, const figure_bracket& error,
               std::uint64_t number) const {
        j.geometry = g;
        j.eval = std::move(e);
        j.error = error;
        j.number = number;
        j.fit = fitness_of(options_, j.eval, j.error, g);
    }

    // The exact error of a case judged with it bracketed: judged again, exactly.
    void settle(judged_case& j) {
        if (j.error.exact()) return;
        name_case(settling_, j.geometry, "evaluation", j.number, start_index_);
        const case_in_progress announced(settling_);
        auto [eval, error] = evaluate_bracketed(target_, settling_, options_.objective, false);
        score(j, j.geometry, std::move(eval), error, j.number);
    }

    // compare(a's score, b's): from their brackets, or settled where those overlap.
    comparison rank(judged_case& a, judged_case& b) {
        if (const uncertain_comparison c = compare_fitness(a.fit, b.fit)) return *c;
        settle(a);
        settle(b);
        return *compare_fitness(a.fit, b.fit);
    }

    void note(judged_case& j, std::uint64_t index) {
        if (options_.objective == hunt_objective::misclass) {
            if (j.fit.tier == 1 && !done()) result_.finds.push_back(make_find(j, index));
            return;
        }
        // A new largest error: possible only where the bracket reaches past the largest so far.
        if (j.fit.tier == 0 && j.error.upper > 0 && (!best_ || j.error.upper > best_->found_eval.error)) {
            settle(j);
            if (j.eval.error > 0 && (!best_ || j.eval.error > best_->found_eval.error)) best_ = make_find(j, index);
        }
        if (is_disagreement(j.eval.verdict) && result_.disagreements++ == 0)
            result_.first_disagreement = make_find(j, index);
    }

    hunt_find make_find(const judged_case& j, std::uint64_t index) const {
        hunt_find f;
        f.found = f.shrunk = j.geometry;
        f.found_eval = f.shrunk_eval = j.eval;
        f.found_bits = f.shrunk_bits = significant_bits(j.geometry);
        f.evaluation = result_.evaluations;
        f.seconds = elapsed();
        f.start_index = index;
        return f;
    }

    // One to three inputs moved by ±2^j ulps, j uniform in [0, p − 1]. A moved
    // direction is renormalised (in the working precision) for a variant that
    // assumes a unit direction.
    ray_sphere<double> mutate(const ray_sphere<double>& g) {
        ray_sphere<double> out = g;
        const int p = significand_bits(target_.prec);
        const std::uint64_t moves = 1 + random_.below(3);
        bool direction_moved = false;
        for (std::uint64_t m = 0; m < moves; ++m) {
            const int i = static_cast<int>(random_.below(10));
            const std::int64_t size = std::int64_t{1} << random_.below(static_cast<std::uint64_t>(p));
            input_at(out, i) = step_in(target_.prec, input_at(out, i), random_.coin() ? size : -size);
            direction_moved = direction_moved || (i >= 3 && i < 6);
        }
        if (direction_moved && target_.subject.promises.assumes_unit_direction) {
            const double n = std::sqrt(length_squared(out.direction));
            if (n > 0 && std::isfinite(n))
                out.direction = {round_to(target_.prec, out.direction.x / n),
                                 round_to(target_.prec, out.direction.y / n),
                                 round_to(target_.prec, out.direction.z / n)};
        }
        return out;
    }

    // Greedy shrinking: whole-scene simplifications first (translate c to 0,
    // scale to unit size), then each input zeroed or cut to the fewest leading
    // bits that keep the failure; repeated until nothing changes.
    void shrink(hunt_find& f) {
        std::uint64_t budget = options_.shrink_evaluations;
        const auto fails_same = [&](const ray_sphere<double>& g) {
            // A sphere of radius 0 is a point: no find to act on.
            if (budget == 0 || !(g.radius > 0)) return false;
            --budget;
            ++result_.shrink_evaluations;
            const hunt_evaluation e =
                judge_batch({g}, "shrink", result_.shrink_evaluations - 1, f.start_index, true).front().eval;
            if (!same_failure(options_, f.found_eval, e)) return false;
            if (significant_bits(g) > f.shrunk_bits) return false;
            f.shrunk = g;
            f.shrunk_eval = e;
            f.shrunk_bits = significant_bits(g);
            return true;
        };
        for (bool changed = true; changed && budget > 0;) {
            changed = false;
            // The scene translated so that c = 0 (o − c rounded in the precision;
            // a segment's p1, in the direction field, moved with it).
            if (f.shrunk.centre != vec3<double>{}) {
                ray_sphere<double> t = f.shrunk;
                const auto translated = [&](const vec3<double>& p) {
                    return vec3<double>{round_to(target_.prec, p.x - t.centre.x),
                                        round_to(target_.prec, p.y - t.centre.y),
                                        round_to(target_.prec, p.z - t.centre.z)};
                };
                t.origin = translated(t.origin);
                if (options_.segments) t.direction = translated(t.direction);
                t.centre = {};
                changed = fails_same(t) || changed;
            }
            // o, c, r (and a segment's p1) scaled by a power of two towards
            // r = 1, a ray's d towards |d| = 1 (exact scalings).
            if (f.shrunk.radius > 0) {
                const int k = -std::ilogb(f.shrunk.radius);
                if (k != 0) {
                    ray_sphere<double> t = f.shrunk;
                    t.origin = std::ldexp(1.0, k) * t.origin;
                    t.centre = std::ldexp(1.0, k) * t.centre;
                    t.radius = std::ldexp(t.radius, k);
                    if (options_.segments) t.direction = std::ldexp(1.0, k) * t.direction;
                    changed = fails_same(rounded_in(target_.prec, t)) || changed;
                }
            }
            const double d_max = std::max({std::fabs(f.shrunk.direction.x), std::fabs(f.shrunk.direction.y),
                                           std::fabs(f.shrunk.direction.z)});
            if (!options_.segments && d_max > 0 && std::ilogb(d_max) != 0) {
                ray_sphere<double> t = f.shrunk;
                t.direction = std::ldexp(1.0, -std::ilogb(d_max)) * t.direction;
                changed = fails_same(rounded_in(target_.prec, t)) || changed;
            }
            for (int i = 0; i < 10 && budget > 0; ++i) {
                const double x = input_at(f.shrunk, i);
                if (x == 0) continue;
                ray_sphere<double> t = f.shrunk;
                input_at(t, i) = 0;
                if (fails_same(t)) {
                    changed = true;
                    continue;
                }
                const int have = significand_bits_in(x);
                for (int bits = 1; bits < have && budget > 0; ++bits) {
                    input_at(t, i) = round_to(target_.prec, keep_bits(x, bits));
                    if (fails_same(t)) {
                        changed = true;
                        break;
                    }
                }
            }
        }
    }

    // `steps` up (or down) as step_in takes them, at most 2^63 − 1 of them
    // (two doubles of opposite signs can be further apart; a bisection then
    // starts from the nearer half).
    static std::int64_t signed_steps(std::uint64_t steps, bool up) {
        const auto most = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
        const auto magnitude = static_cast<std::int64_t>(std::min(steps, most));
        return up ? magnitude : -magnitude;
    }

    // Greedy shrinking toward the start case: each input that differs from
    // the start's is set back to it, or else moved as near it as keeps the
    // failure (a bisection on the steps between them); repeated until
    // nothing changes. A case is kept only when it is nearer the start in
    // all (fewer steps over the ten inputs).
    void shrink_toward_start(hunt_find& f) {
        const ray_sphere<double> origin_case = rounded_in(target_.prec, start_(f.start_index));
        const auto distance = [&](const ray_sphere<double>& g) {
            std::uint64_t steps = 0;
            for (int i = 0; i < 10; ++i)
                steps += ulps_between_in(target_.prec, input_at(g, i), input_at(origin_case, i));
            return steps;
        };
        std::uint64_t budget = options_.shrink_evaluations;
        std::uint64_t kept_distance = distance(f.shrunk);
        const auto fails_same = [&](const ray_sphere<double>& g) {
            if (budget == 0 || !(g.radius > 0)) return false;
            const std::uint64_t d = distance(g);
            if (d >= kept_distance) return false;
            --budget;
            ++result_.shrink_evaluations;
            const hunt_evaluation e =
                judge_batch({g}, "shrink", result_.shrink_evaluations - 1, f.start_index, true).front().eval;
            if (!same_failure(options_, f.found_eval, e)) return false;
            f.shrunk = g;
            f.shrunk_eval = e;
            f.shrunk_bits = significant_bits(g);
            kept_distance = d;
            return true;
        };
        for (bool changed = true; changed && budget > 0;) {
            changed = false;
            for (int i = 0; i < 10 && budget > 0; ++i) {
                const double from = input_at(origin_case, i), now = input_at(f.shrunk, i);
                if (now == from) continue;
                ray_sphere<double> t = f.shrunk;
                input_at(t, i) = from;
                if (fails_same(t)) {
                    changed = true;
                    continue;
                }
                // The failing value nearest the start: between `from` (passes) and `now` (fails).
                const bool now_above = now > from;
                std::uint64_t passing = 0, failing = ulps_between_in(target_.prec, from, now);
                while (failing - passing > 1 && budget > 0) {
                    const std::uint64_t middle = passing + (failing - passing) / 2;
                    input_at(t, i) = step_in(target_.prec, from, signed_steps(middle, now_above));
                    if (fails_same(t)) {
                        failing = middle;
                        changed = true;
                    } else {
                        passing = middle;
                    }
                }
            }
        }
        // Then moves of one to three inputs at once, each toward the start by
        // 2^j of the steps between (j uniform): a failure near a tangency is
        // kept only by moving inputs together, along the surface where the
        // class changes; 400 moves in a row that keep nothing end it.
        for (std::uint64_t stale = 0; budget > 0 && stale < 400 && kept_distance > 0; ++stale) {
            ray_sphere<double> t = f.shrunk;
            const std::uint64_t moves = 1 + random_.below(3);
            for (std::uint64_t m = 0; m < moves; ++m) {
                const int i = static_cast<int>(random_.below(10));
                const double from = input_at(origin_case, i), now = input_at(t, i);
                const std::uint64_t apart = ulps_between_in(target_.prec, from, now);
                if (apart == 0) continue;
                const std::uint64_t size =
                    std::uint64_t{1} << random_.below(static_cast<std::uint64_t>(std::bit_width(apart)));
                input_at(t, i) = step_in(target_.prec, now, signed_steps(std::min(size, apart), now < from));
            }
            if (fails_same(t)) stale = 0;
        }
        f.inputs_changed = 0;
        for (int i = 0; i < 10; ++i) f.inputs_changed += input_at(f.shrunk, i) != input_at(origin_case, i);
        f.steps_from_start = distance(f.shrunk);
    }

    const audit_target& target_;
    const hunt_start& start_;
    hunt_options options_;
    const hunt_judge& judge_;
    hunt_random random_;
    std::chrono::steady_clock::time_point began_;
    hunt_result result_;
    std::optional<hunt_find> best_;
    std::uint64_t start_index_ = 0;  // the start case the search is on
    mutable std::uint64_t clock_read_at_ = 0;  // the evaluation count when exhausted() last read the clock
    mutable bool out_of_time_ = false;         // what it read: the time budget is spent
    // Reused from batch to batch: the cases moved (or drawn), named and judged.
    std::vector<ray_sphere<double>> moved_;
    std::vector<corpus_case> cases_;
    std::vector<judged_case> judged_;
    std::string source_;  // "hunt, searching from start case S" for source_start_ S
    std::optional<std::uint64_t> source_start_;
    corpus_case settling_;  // the case being judged again exactly
};

}  // namespace

ray_sphere<double> segment_search_inputs(const corpus_case& segment) {
    ray_sphere<double> inputs = segment.geometry;
    inputs.direction = segment.segment_end.value_or(segment.geometry.origin + segment.geometry.direction);
    return inputs;
}

void set_segment_candidate(corpus_case& c, const ray_sphere<double>& inputs) {
    c.geometry.centre = inputs.centre;
    c.geometry.radius = inputs.radius;
    make_segment(c, inputs.origin, inputs.direction);
}

hunt_evaluation evaluate_for_hunt(const audit_target& target, const ray_sphere<double>& input,
                                  hunt_objective objective) {
    corpus_case c;
    c.id = "hunt";
    c.geometry = input;
    return evaluate_for_hunt(target, c, objective);
}

hunt_evaluation evaluate_for_hunt(const audit_target& target, const corpus_case& c, hunt_objective objective) {
    return evaluate_bracketed(target, c, objective, false).first;
}

int significant_bits(const ray_sphere<double>& g) {
    int total = 0;
    for (int i = 0; i < 10; ++i) total += significand_bits_in(input_at(g, i));
    return total;
}

std::uint64_t shard_search_seed(std::uint64_t seed, std::size_t shard_index, std::size_t shard_count) {
    if (shard_count == 1) return seed;
    return splitmix64_finalise(seed + golden_gamma * shard_index);
}

hunt_result hunt(const audit_target& target, const hunt_start& start, const hunt_options& options,
                 const hunt_judge& judge) {
    return hunter(target, start, options, judge).run();
}

}  // namespace rayverify
