// The fast (filtered) oracle against the reference route: identical answers,
// bit for bit, on every shipped corpus file and on random cases, adversarial
// ones included (near-tangent, far spheres, huge and tiny exponents, origins
// on the surface, exactly representable roots, rounding ties). Every random
// test prints its seed; a failure prints the case as hex floats.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/hostile_fp_plugins.h"
#include "core/float_bits.h"
#include "core/fp_environment.h"
#include "corpus/corpus_io.h"
#include "oracle/oracle.h"
#include "oracle/static_filter.h"
#include "support/random_geometry.h"
#include "support/sanitized.h"

namespace rayverify {
namespace {

namespace fs = std::filesystem;
constexpr double inf = std::numeric_limits<double>::infinity();

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

std::string hex(double x) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%a", x);
    return buffer;
}

std::string describe(const ray_sphere<double>& g, std::optional<double> tmin, std::optional<double> tmax) {
    std::ostringstream out;
    out << "o " << hex(g.origin.x) << " " << hex(g.origin.y) << " " << hex(g.origin.z) << "  d " << hex(g.direction.x)
        << " " << hex(g.direction.y) << " " << hex(g.direction.z) << "  c " << hex(g.centre.x) << " "
        << hex(g.centre.y) << " " << hex(g.centre.z) << "  r " << hex(g.radius);
    if (tmin || tmax) out << "  [" << (tmin ? hex(*tmin) : "-") << ", " << (tmax ? hex(*tmax) : "-") << "]";
    return out.str();
}

ray_sphere<double> float_inputs(const ray_sphere<double>& g) { return rounded_to<double>(rounded_to<float>(g)); }

// What a comparison checked, for the tallies the tests print and assert on.
struct comparison_tally {
    std::size_t cases = 0, filter_stage = 0, ulp_queries = 0;
    std::size_t partial = 0;  // solve_exact_roots compared (both depths), static filter or not
};

// Values to probe the ULP and comparison queries with, around an exact value
// whose rounding is `rounded` in precision p: the rounding itself, its
// neighbours, a few ulps away, far away, zero, a non-finite value.
std::vector<double> probes(double rounded, precision p, std::mt19937_64& rng) {
    std::vector<double> out = {rounded, 0.0, inf, rounded * 3 + 1};
    const auto step = [p](double x, double toward) {
        return p == precision::binary32 ? double(std::nextafter(float(x), float(toward))) : std::nextafter(x, toward);
    };
    double up = rounded, down = rounded;
    const int steps = 1 + static_cast<int>(rng() % 5);
    for (int k = 0; k < steps; ++k) {
        up = step(up, inf);
        down = step(down, -inf);
        if (k == 0 || k == steps - 1) {
            out.push_back(up);
            out.push_back(down);
        }
    }
    // A double between the precision's neighbours (float: a value a float variant cannot return).
    out.push_back(std::nextafter(rounded, inf));
    return out;
}

// A filtered route and its reference: the oracle's own, and the unit-direction
// idealisation's (a taken to be 1; it has no interval).
struct route {
    const char* name;
    exact_solution (*fast)(const ray_sphere<double>&, precision, std::optional<double>, std::optional<double>);
    exact_solution (*reference)(const ray_sphere<double>&, precision, std::optional<double>, std::optional<double>);
};

const route routes[] = {
    {"solve_exact", solve_exact, solve_exact_reference},
    {"solve_exact_unit_direction",
     [](const ray_sphere<double>& g, precision p, std::optional<double>, std::optional<double>) {
         return solve_exact_unit_direction(g, p);
     },
     [](const ray_sphere<double>& g, precision p, std::optional<double>, std::optional<double>) {
         return solve_exact_unit_direction_reference(g, p);
     }},
};

// Fast and reference solutions of one case agree on every field and query.
testing::AssertionResult identical(const route& way, const ray_sphere<double>& g, precision p,
                                   std::optional<double> tmin, std::optional<double> tmax, bool with_queries,
                                   std::mt19937_64& rng, comparison_tally& tally) {
    const exact_solution fast = way.fast(g, p, tmin, tmax);
    const exact_solution ref = way.reference(g, p, tmin, tmax);
    ++tally.cases;
    if (fast.valid() && fast.stage == oracle_stage::filter) ++tally.filter_stage;
    std::ostringstream why;
    const auto check = [&](bool ok, const std::string& what) {
        if (!ok) why << "\n  " << what;
    };
    check(fast.invalid == ref.invalid, "invalid differs");
    check(fast.prec == ref.prec, "precision differs");
    // The partial answers (class and signs; roots rounded) of the true
    // quadratic, which take no interval: the reference's, field by field.
    if (&way == &routes[0] && ref.invalid != invalid_reason::bad_interval) {
        for (const oracle_depth depth : {oracle_depth::class_and_signs, oracle_depth::roots_rounded}) {
            const exact_roots part = solve_exact_roots(g, p, depth);
            const std::string at = depth == oracle_depth::class_and_signs ? "class_and_signs: " : "roots_rounded: ";
            check(part.invalid == ref.invalid, at + "invalid differs");
            if (!part.valid() || !ref.valid()) continue;
            check(part.cls == ref.cls, at + "class differs");
            if (ref.cls == line_class::miss) continue;
            for (root_index i : {root_index::near_root, root_index::far_root}) {
                const exact_root& mine = i == root_index::near_root ? part.near_root : part.far_root;
                check(mine.sign == ref.root(i).sign, at + "sign differs");
                if (depth == oracle_depth::roots_rounded)
                    check(same_bits(mine.rounded, ref.root(i).rounded),
                          at + "rounded: " + hex(mine.rounded) + ", reference " + hex(ref.root(i).rounded));
            }
        }
        ++tally.partial;
    }
    if (ref.valid() && fast.valid()) {
        check(fast.cls == ref.cls, std::string("class: fast ") + line_class_name(fast.cls) + ", reference " +
                                       line_class_name(ref.cls));
        check(ref.stage == oracle_stage::exact, "reference stage is not exact");
        if (ref.cls != line_class::miss) {
            for (root_index i : {root_index::near_root, root_index::far_root}) {
                const std::string name = i == root_index::near_root ? "near" : "far";
                check(fast.root(i).sign == ref.root(i).sign, name + " sign differs");
                check(same_bits(fast.root(i).rounded, ref.root(i).rounded),
                      name + " rounded: fast " + hex(fast.root(i).rounded) + ", reference " + hex(ref.root(i).rounded));
            }
            check(fast.nearest_in_front == ref.nearest_in_front, "nearest_in_front differs");
            for (int axis = 0; axis < 3; ++axis)
                check(same_bits(fast.hit_point()[axis], ref.hit_point()[axis]),
                      "hit_point[" + std::to_string(axis) + "]: fast " + hex(fast.hit_point()[axis]) + ", reference " +
                          hex(ref.hit_point()[axis]));
            if (with_queries) {
                if (ref.cls == line_class::two_hit) {
                    const double middle = 0.5 * ref.near_root.rounded + 0.5 * ref.far_root.rounded;
                    for (double v : {middle, std::nextafter(middle, inf), std::nextafter(middle, -inf), 0.0})
                        if (std::isfinite(v))
                            check(fast.compare_to_midpoint(v) == ref.compare_to_midpoint(v),
                                  "compare_to_midpoint(" + hex(v) + ") differs");
                }
                for (root_index i : {root_index::near_root, root_index::far_root}) {
                    const std::string name = i == root_index::near_root ? "near" : "far";
                    for (double v : probes(ref.root(i).rounded, p, rng)) {
                        ++tally.ulp_queries;
                        if (std::isfinite(v))
                            check(fast.compare_to_root(v, i) == ref.compare_to_root(v, i),
                                  name + " compare_to_root(" + hex(v) + ") differs");
                        const double a = fast.root_ulp_error(i, v), b = ref.root_ulp_error(i, v);
                        check(same_bits(a, b), name + " root_ulp_error(" + hex(v) + "): fast " + hex(a) +
                                                   ", reference " + hex(b));
                        // The hunter's bracket holds the error, correctly rounded, wherever it is formed.
                        if (std::isfinite(v))
                            if (const std::optional<figure_bracket> bracket = fast.root_ulp_error_bracket(i, v))
                                check(bracket->lower <= b && b <= bracket->upper,
                                      name + " root_ulp_error_bracket(" + hex(v) + ") = [" + hex(bracket->lower) +
                                          ", " + hex(bracket->upper) + "] leaves out " + hex(b));
                    }
                    for (int axis = 0; axis < 3; ++axis) {
                        const double fr = fast.rounded_hit_coordinate(i, axis);
                        const double rr = ref.rounded_hit_coordinate(i, axis);
                        check(same_bits(fr, rr), name + " rounded_hit_coordinate differs: fast " + hex(fr) +
                                                     ", reference " + hex(rr));
                        for (double v : {rr, std::nextafter(rr, inf), std::nextafter(rr, -inf), rr * 2 + 1}) {
                            if (std::isfinite(v))
                                check(fast.compare_to_hit_coordinate(v, i, axis) == ref.compare_to_hit_coordinate(v, i, axis),
                                      name + " compare_to_hit_coordinate(" + hex(v) + ") differs");
                            ++tally.ulp_queries;
                            const double a = fast.hit_point_ulp_error(i, axis, v);
                            const double b = ref.hit_point_ulp_error(i, axis, v);
                            check(same_bits(a, b), name + " hit_point_ulp_error(" + hex(v) + "): fast " + hex(a) +
                                                       ", reference " + hex(b));
                            // The audit's bracket holds the error wherever it is formed.
                            if (std::isfinite(v))
                                if (const std::optional<figure_bracket> bracket =
                                        fast.hit_point_ulp_error_bracket(i, axis, v))
                                    check(bracket->lower <= b && b <= bracket->upper,
                                          name + " hit_point_ulp_error_bracket(" + hex(v) + ") = [" +
                                              hex(bracket->lower) + ", " + hex(bracket->upper) + "] leaves out " +
                                              hex(b));
                        }
                    }
                }
            }
        }
    }
    if (ref.valid() && fast.valid() && with_queries)
        for (double x : {0.0, 1e-7, -1e-7, 1.0, -1.0})
            check(fast.compare_to_discriminant(x) == ref.compare_to_discriminant(x),
                  "compare_to_discriminant(" + hex(x) + ") differs");
    if (why.str().empty()) return testing::AssertionSuccess();
    return testing::AssertionFailure() << way.name << ", " << precision_name(p) << " " << describe(g, tmin, tmax)
                                       << why.str();
}

// Both precisions of a case (float when its inputs are representable there),
// on the oracle's route and, with `unit_route`, the unit-direction design's too.
void compare_case(const ray_sphere<double>& g, std::optional<double> tmin, std::optional<double> tmax,
                  bool with_queries, std::mt19937_64& rng, comparison_tally& tally, bool unit_route = true) {
    for (const route& way : routes) {
        if (!unit_route && &way != &routes[0]) continue;
        EXPECT_TRUE(identical(way, g, precision::binary64, tmin, tmax, with_queries, rng, tally));
        if (validity<float>(g) != invalid_reason::none) continue;
        const auto narrow = [](std::optional<double> t) -> std::optional<double> {
            if (!t) return t;
            return double(float(*t));
        };
        EXPECT_TRUE(identical(way, float_inputs(g), precision::binary32, narrow(tmin), narrow(tmax), with_queries, rng,
                              tally));
    }
}

// ---------------------------------------------------------------------------
// Every shipped corpus file, both precisions, with every query.

TEST(FastOracleCorpus, IdenticalToReferenceOnEveryShippedFile) {
    const fs::path root = fs::path(RAYVERIFY_SOURCE_DIR) / "corpus";
    std::vector<fs::path> files = corpus_files(root);
    for (const fs::path& f : corpus_files(root / "edge")) files.push_back(f);
    ASSERT_GE(files.size(), 20u);
    std::mt19937_64 rng(7);
    comparison_tally tally;
    std::size_t at = 0;
    for (const fs::path& file : files) {
        for (const corpus_case& c : read_corpus_file(file)) {
            if (at++ % test_support::sanitized_stride != 0) continue;
            SCOPED_TRACE(c.source);
            compare_case(c.geometry, c.tmin, c.tmax, true, rng, tally);
        }
    }
    std::printf("corpus: %zu solutions compared (%zu settled by the filter), %zu ULP queries, %zu partial answers; "
                "one case in %zu\n",
                tally.cases, tally.filter_stage, tally.ulp_queries, tally.partial, test_support::sanitized_stride);
    EXPECT_GT(tally.cases, 10000u / test_support::sanitized_stride);
}

// ---------------------------------------------------------------------------
// Random regimes.

using test_support::aimed_uniform_case;
using test_support::integer_case;
using test_support::near_tangent_case;
using test_support::on_surface_case;
using test_support::scaled;
using test_support::tie_case;
using test_support::uniform;
using test_support::uniform_point;
using test_support::unit_vector;

// Far sphere: c at distance 10^k (k in [2, 20]) from o, r = distance · 10^−j.
ray_sphere<double> far_case(std::mt19937_64& rng) {
    const vec3<double> o = uniform_point(rng, 10);
    const double distance = std::pow(10.0, uniform(rng, 2, 20));
    const vec3<double> c = o + distance * unit_vector(rng);
    const double r = distance * std::pow(10.0, -uniform(rng, 0, 12));
    const vec3<double> target = c + (r * uniform(rng, 0, 1.5)) * unit_vector(rng);
    return {o, target - o, c, r};
}

// Exponents: a uniform case with positions scaled by 2^s and d by 2^s′,
// s, s′ spread across and beyond the filter's range [2^−80, 2^80] (and into
// float's overflow range).
ray_sphere<double> exponent_case(std::mt19937_64& rng) {
    ray_sphere<double> g = aimed_uniform_case(rng);
    const int s = static_cast<int>(rng() % 2) == 0 ? static_cast<int>(rng() % 201) - 100
                                                   : static_cast<int>(rng() % 1901) - 950;
    const int sd = static_cast<int>(rng() % 181) - 90;
    g.origin = scaled(g.origin, s);
    g.centre = scaled(g.centre, s);
    g.radius = std::ldexp(g.radius, s);
    g.direction = scaled(g.direction, sd);
    return g;
}

struct regime {
    const char* name;
    ray_sphere<double> (*make)(std::mt19937_64&);
};

const regime regimes[] = {
    {"uniform", aimed_uniform_case},
    {"near_tangent", near_tangent_case},
    {"far", far_case},
    {"exponents", exponent_case},
    {"surface", on_surface_case},
    {"integers", integer_case},
    {"tie_binary64", [](std::mt19937_64& rng) { return tie_case(rng, 53); }},
    {"tie_binary32", [](std::mt19937_64& rng) { return tie_case(rng, 24); }},
};

// An interval for some cases: around a random point, or one-sided, or infinite.
void random_interval(std::mt19937_64& rng, std::optional<double>& tmin, std::optional<double>& tmax) {
    tmin.reset();
    tmax.reset();
    switch (rng() % 6) {
        case 0: tmin = 0.0; break;
        case 1: tmin = uniform(rng, -5, 5), tmax = *tmin + uniform(rng, 0, 20); break;
        case 2: tmax = uniform(rng, -5, 30); break;
        case 3: tmin = -inf, tmax = inf; break;
        default: break;
    }
}

// `count` cases of each regime from `seed`; every `query_every`-th case also
// compares every ULP and comparison query.
comparison_tally sweep(std::uint64_t seed, int count, int query_every) {
    comparison_tally tally;
    for (const regime& r : regimes) {
        for (int i = 0; i < count; ++i) {
            const std::uint64_t case_seed = seed + static_cast<std::uint64_t>(i);
            std::mt19937_64 rng(case_seed ^ std::hash<std::string>{}(r.name));
            SCOPED_TRACE(testing::Message() << "regime " << r.name << ", seed " << case_seed);
            const ray_sphere<double> g = r.make(rng);
            std::optional<double> tmin, tmax;
            random_interval(rng, tmin, tmax);
            // The unit-direction route on one case in four (its reference is all GMP).
            compare_case(g, tmin, tmax, i % query_every == 0, rng, tally, i % 4 == 0);
            if (testing::Test::HasFailure()) return tally;  // one failure is enough to read
        }
    }
    return tally;
}

TEST(FastOracleRandom, IdenticalToReference) {
    const std::uint64_t seed = 20261122;
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    const comparison_tally tally = sweep(seed, test_support::sweep_size(6000), 8);
    std::printf("random: %zu solutions compared (%zu settled by the filter), %zu ULP queries\n", tally.cases,
                tally.filter_stage, tally.ulp_queries);
}

TEST(LongSweepFastOracle, IdenticalToReferenceOnMillions) {
    const std::vector<variant> hostile = test_support::load_hostile_fp_plugins();  // the truth holds with them loaded
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    const comparison_tally tally = sweep(seed, 150000, 16);
    std::printf("random: %zu solutions compared (%zu settled by the filter), %zu ULP queries\n", tally.cases,
                tally.filter_stage, tally.ulp_queries);
}

// ---------------------------------------------------------------------------
// The stage is honest: the filter settles ordinary cases, exact arithmetic
// runs where the filter cannot decide.

TEST(FastOracleStage, FilterSettlesUniformCases) {
    std::mt19937_64 rng(11);
    int filter = 0;
    const int n = 2000;
    for (int i = 0; i < n; ++i) filter += solve_exact(aimed_uniform_case(rng), precision::binary64).stage == oracle_stage::filter;
    EXPECT_GE(filter, n * 99 / 100) << filter << " of " << n;
}

// The partial answers stop the static filter early: whatever the whole
// static filter settles, each shallower depth settles too (it answers a
// prefix of the same questions), and on uniform cases it settles nearly all,
// so that solve_exact_roots seldom needs a whole solution.
TEST(FastOracleStage, PartialAnswersEndInTheStaticFilterOnUniformCases) {
    std::mt19937_64 rng(13);
    const int n = 2000;
    int settled[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
        const ray_sphere<double> g = aimed_uniform_case(rng);
        bool deeper_settled = false;
        for (const oracle_depth depth : {oracle_depth::everything, oracle_depth::roots_rounded,
                                         oracle_depth::class_and_signs}) {
            oracle_internal::filtered_case f;
            const bool ok = oracle_internal::static_filter_case(g, precision::binary64, f, depth);
            EXPECT_TRUE(ok || !deeper_settled) << "a shallower depth failed where a deeper one settled";
            deeper_settled = ok;
            settled[static_cast<int>(depth)] += ok;
        }
    }
    EXPECT_GE(settled[static_cast<int>(oracle_depth::roots_rounded)], n * 99 / 100);
    EXPECT_GE(settled[static_cast<int>(oracle_depth::class_and_signs)], n * 99 / 100);
}

// A batch answers each case as a call of its own would, field by field, in
// every regime (the static filter's cases and those it leaves to the whole
// solution), also when foreign code left the thread in another environment
// before it: the batch restores the IEEE default once, before its first case.
TEST(FastOracleStage, ABatchAnswersAsOneCallPerCase) {
    std::vector<ray_sphere<double>> cases;
    std::uint64_t seed = 20261203;
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    for (const regime& r : regimes) {
        std::mt19937_64 rng(seed++);
        for (int i = 0; i < 300; ++i) cases.push_back(r.make(rng));
    }
    const fp_state hostile = *fp_state_for(*parse_fp_environment("ftz+daz+upward"));
    // Whatever fails below, the tests after this one run in the IEEE default.
    struct ieee_default_on_exit {
        ~ieee_default_on_exit() { set_fp_state(ieee_default_fp_state()); }
    } restore;
    // Both roots rounded, a batch answers in two passes over each chunk of 64
    // cases: the misses first, then the rest; the regimes mix both in a chunk.
    for (const auto& [depth, prec] : {std::pair{oracle_depth::class_and_signs, precision::binary64},
                                      {oracle_depth::roots_rounded, precision::binary64},
                                      {oracle_depth::roots_rounded, precision::binary32}}) {
        std::vector<exact_roots> one_by_one;
        for (const ray_sphere<double>& g : cases) one_by_one.push_back(solve_exact_roots(g, prec, depth));
        std::vector<exact_roots> batch(cases.size());
        set_fp_state(hostile);
        solve_exact_roots(cases, prec, depth, batch);
        ASSERT_TRUE(is_ieee_default(current_fp_state())) << describe_fp_state(current_fp_state());
        std::size_t two_hits = 0, misses = 0;
        for (std::size_t i = 0; i < cases.size(); ++i) {
            SCOPED_TRACE(testing::Message() << "case " << i << " (" << regimes[i / 300].name << ", "
                                            << (prec == precision::binary64 ? "binary64" : "binary32") << "): "
                                            << describe(cases[i], std::nullopt, std::nullopt));
            const exact_roots &mine = batch[i], &alone = one_by_one[i];
            ASSERT_EQ(mine.invalid, alone.invalid);
            ASSERT_EQ(mine.cls, alone.cls);
            for (const auto& [m, a] : {std::pair{mine.near_root, alone.near_root}, {mine.far_root, alone.far_root}}) {
                ASSERT_EQ(m.sign, a.sign);
                ASSERT_TRUE(same_bits(m.rounded, a.rounded)) << hex(m.rounded) << " alone " << hex(a.rounded);
            }
            two_hits += mine.cls == line_class::two_hit;
            misses += mine.cls == line_class::miss;
        }
        std::printf("%zu two-hit lines, %zu misses\n", two_hits, misses);
        EXPECT_GT(two_hits, cases.size() / 4) << "most regimes aim at the sphere";
        EXPECT_GT(misses, cases.size() / 20) << "some cases miss";
    }
}

// A double's ULP error needs its root to about 2^−150 (the error of a
// correctly rounded answer is a fraction of an ulp, printed to every digit):
// the refined enclosures settle those queries on ordinary cases, with the
// reference's answers bit for bit and no exact arithmetic.
TEST(FastOracleStage, RefinedEnclosuresSettleDoubleUlpErrorsOfUniformCases) {
    std::mt19937_64 rng(17);
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    std::size_t queries = 0;
    std::uint64_t exact_queries = 0, refined_queries = 0;
    for (int i = 0; i < 1000; ++i) {
        const ray_sphere<double> g = aimed_uniform_case(rng);
        const exact_solution fast = solve_exact(g, precision::binary64);
        if (fast.cls != line_class::two_hit || !fast.nearest_in_front) continue;
        const exact_solution reference = solve_exact_reference(g, precision::binary64);
        const root_index front = *fast.nearest_in_front;
        const double t = fast.root(front).rounded;
        for (const double value : {t, next_up(t), next_down(t), t + 64 * (next_up(t) - t)}) {
            counts = {};
            const double error = fast.root_ulp_error(front, value);
            exact_queries += counts.ulp_errors.exact;
            refined_queries += counts.ulp_errors.expansion;
            ASSERT_EQ(std::bit_cast<std::uint64_t>(error),
                      std::bit_cast<std::uint64_t>(reference.root_ulp_error(front, value)))
                << "case " << i << " value " << value;
            ++queries;
        }
        for (int axis = 0; axis < 3; ++axis) {
            const double p = fast.hit_point()[axis];
            for (const double value : {p, next_up(p), next_down(p)}) {
                counts = {};
                const double error = fast.hit_point_ulp_error(front, axis, value);
                exact_queries += counts.ulp_errors.exact;
                refined_queries += counts.ulp_errors.expansion;
                ASSERT_EQ(std::bit_cast<std::uint64_t>(error),
                          std::bit_cast<std::uint64_t>(reference.hit_point_ulp_error(front, axis, value)))
                    << "case " << i << " axis " << axis << " value " << value;
                ++queries;
            }
        }
    }
    std::printf("%zu ULP queries: %llu by refined enclosures, %llu exactly\n", queries,
                static_cast<unsigned long long>(refined_queries), static_cast<unsigned long long>(exact_queries));
    EXPECT_GT(queries, 3000u);
    EXPECT_GT(refined_queries, queries / 4);
    EXPECT_EQ(exact_queries, 0u);
}

// A unit-direction design that is a miss keeps its own quadratic: its Δ′ is
// b′² − C (a taken to be 1), not the true b′² − aC. far_sphere-1-000008 of the
// shipped corpus: a direction normalised in double, a sphere 3·10^8 away; the
// true line meets it, the unit design misses, and the two Δ′ lie on either
// side of seed003_reduced's tangent threshold 1e−7. The reference route once
// rebuilt the true Δ′ for a design that missed (a false_tangent's cause came
// out algorithmic instead of tangent_threshold).
TEST(FastOracleUnitDirection, AMissKeepsTheUnitDiscriminant) {
    const ray_sphere<double> g{{0x1.e70ccffb3f84p-3, -0x1.93d3e9ade454p-2, -0x1.765354a800b8p-2},
                               {-0x1.84c738e89f704p-2, 0x1.d4815952de202p-1, 0x1.16d889eaf1fb1p-3},
                               {-0x1.5e708b971ca06p+27, 0x1.a64df7c8fe6b7p+28, 0x1.f6b230e62d047p+25},
                               0x1.e0b3733da9d3ep+0};
    const exact_solution line = solve_exact(g, precision::binary64);
    ASSERT_EQ(line.cls, line_class::two_hit);
    EXPECT_EQ(line.compare_to_discriminant(1e-7), comparison::smaller);  // Δ′ > 1e-7
    for (const auto solve : {solve_exact_unit_direction, solve_exact_unit_direction_reference}) {
        const exact_solution unit = solve(g, precision::binary64);
        ASSERT_EQ(unit.cls, line_class::miss);
        EXPECT_EQ(unit.compare_to_discriminant(0.0), comparison::larger);  // Δ′ < 0
        EXPECT_EQ(unit.compare_to_discriminant(1e-7), comparison::larger);
        const exact_solution copy = unit;  // a copy asks the same quadratic
        EXPECT_EQ(copy.compare_to_discriminant(1e-7), comparison::larger);
    }
}

// Exact tangents whose hit point has exactly representable coordinates: a
// variant that returns them has an error of exactly 0, which no enclosure can
// show; the expansions do, with the reference's answers and no GMP.
TEST(FastOracleStage, ExpansionsSettleExactHitCoordinatesOfTangents) {
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    std::size_t queries = 0, exact_zero = 0;
    std::uint64_t gmp = 0;
    for (const corpus_case& c :
         read_corpus_file(fs::path(RAYVERIFY_SOURCE_DIR) / "corpus" / "tangent_exact.txt")) {
        for (precision p : {precision::binary64, precision::binary32}) {
            const ray_sphere<double> g = p == precision::binary32 ? float_inputs(c.geometry) : c.geometry;
            const exact_solution fast = solve_exact(g, p);
            if (fast.stage == oracle_stage::exact || !fast.nearest_in_front) continue;
            const exact_solution reference = solve_exact_reference(g, p);
            const root_index front = *fast.nearest_in_front;
            for (int axis = 0; axis < 3; ++axis) {
                const double v = fast.hit_point()[axis];
                counts = {};
                const double error = fast.hit_point_ulp_error(front, axis, v);
                const comparison side = fast.compare_to_hit_coordinate(v, front, axis);
                gmp += counts.ulp_errors.exact + counts.comparisons.exact;
                ASSERT_TRUE(same_bits(error, reference.hit_point_ulp_error(front, axis, v))) << c.id << " axis " << axis;
                ASSERT_EQ(side, reference.compare_to_hit_coordinate(v, front, axis)) << c.id << " axis " << axis;
                exact_zero += error == 0;
                ++queries;
            }
        }
    }
    std::printf("%zu hit coordinates, %zu of them exactly the correctly rounded value; %llu GMP answers\n", queries,
                exact_zero, static_cast<unsigned long long>(gmp));
    EXPECT_GT(exact_zero, queries / 4);
    EXPECT_EQ(gmp, 0u);
}

TEST(FastOracleStage, ExactWhereTheFilterCannotDecide) {
    // Tangent: Δ′ = 0 exactly, no floating bound can prove a sign; an
    // expansion of Δ′ can, without big numbers.
    const exact_solution tangent = solve_exact({{1, 0, -5}, {0, 0, 1}, {0, 0, 0.25}, 1}, precision::binary64);
    EXPECT_EQ(tangent.cls, line_class::tangent);
    EXPECT_EQ(tangent.stage, oracle_stage::expansion);
    EXPECT_EQ(tangent.near_root.rounded, 5.25);
    // With the tangent point's z exactly 0 its rounding needs the exact
    // state: asked for, not while solving (no hit point is rounded then).
    const exact_solution at_zero = solve_exact({{1, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64);
    EXPECT_EQ(at_zero.cls, line_class::tangent);
    EXPECT_EQ(at_zero.stage, oracle_stage::expansion);
    oracle_stage_counts& counts = oracle_stage_counts_this_thread();
    counts = {};
    EXPECT_EQ(at_zero.hit_point(), (vec3<double>{1, 0, 0}));
    EXPECT_GE(counts.roundings.exact, 1u);
    // Origin on the surface: a root is exactly 0; C's expansion says so.
    const exact_solution surface = solve_exact({{0, 0, -1}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64);
    EXPECT_EQ(surface.near_root.sign, 0);
    EXPECT_EQ(surface.stage, oracle_stage::expansion);
    // A tangent whose root is a rounding midpoint needs the exact route: in
    // float, t = 1 + 2^−24 lies halfway between 1 and 1 + 2^−23.
    const exact_solution tie_tangent =
        solve_exact({{1, 0, -(1 + 0x1p-24)}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary32);
    EXPECT_EQ(tie_tangent.cls, line_class::tangent);
    EXPECT_EQ(tie_tangent.stage, oracle_stage::exact);
    EXPECT_EQ(tie_tangent.near_root.rounded, 1.0);  // the tie goes to the even neighbour
    // Outside the filter's range (2^−80 ≤ |x| ≤ 2^80).
    const exact_solution huge = solve_exact({{0, 0, -0x1p900}, {0, 0, 1}, {0, 0, 0}, 0x1p899}, precision::binary64);
    EXPECT_EQ(huge.cls, line_class::two_hit);
    EXPECT_EQ(huge.stage, oracle_stage::exact);
    // A root on a rounding midpoint: the enclosure straddles it.
    std::mt19937_64 rng(3);
    const exact_solution tie = solve_exact(tie_case(rng, 53), precision::binary64);
    EXPECT_EQ(tie.stage, oracle_stage::exact);
    // An ordinary hit: the filter.
    const exact_solution plain = solve_exact({{0.25, 0.125, -5}, {0, 0, 1}, {0, 0, 0}, 1}, precision::binary64);
    EXPECT_EQ(plain.stage, oracle_stage::filter);
    EXPECT_EQ(plain.cls, line_class::two_hit);
}

// box_meets_sphere (a hit point's bounds against the surface, filter first)
// agrees with its exact route on boxes around points on the sphere, a few
// ulps to a wide margin across, the box's corners pushed in or out by a few
// ulps, spheres of every scale, degenerate boxes and ones outside the
// filter's range; and the filter settles the ordinary ones.
TEST(FastOracleBox, MeetsSphereAsTheExactRouteDoes) {
    const std::uint64_t seed = 20261126;
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(-1, 1), exponent(-90, 90);
    const auto nudged = [&](double x, int ulps) {
        for (int k = 0; k < std::abs(ulps); ++k) x = std::nextafter(x, ulps > 0 ? inf : -inf);
        return x;
    };
    stage_tally& tally = oracle_stage_counts_this_thread().comparisons;
    tally = {};
    int meets = 0, settled = 0, total = 0;
    for (int i = 0; i < 40000; ++i) {
        const double scale = std::ldexp(1.0, static_cast<int>(exponent(rng)));
        const vec3<double> centre{unit(rng) * scale, unit(rng) * scale, unit(rng) * scale};
        const double radius = std::fabs(unit(rng)) * scale + std::ldexp(scale, -60);
        vec3<double> on{unit(rng), unit(rng), unit(rng)};
        const double length = std::sqrt(on.x * on.x + on.y * on.y + on.z * on.z);
        // A point at about the radius from the centre (off the surface by rounding or on purpose).
        const double stretch = i % 3 == 0 ? 1 : 1 + unit(rng) * std::ldexp(1.0, -static_cast<int>(rng() % 60));
        const vec3<double> p{centre.x + on.x / length * radius * stretch, centre.y + on.y / length * radius * stretch,
                             centre.z + on.z / length * radius * stretch};
        const int spread = static_cast<int>(rng() % 4);  // 0: a point; else a box of a few ulps or wider
        double lower[3], upper[3];
        const double point[3] = {p.x, p.y, p.z};
        for (int axis = 0; axis < 3; ++axis) {
            const double width = spread == 3 ? std::fabs(unit(rng)) * radius * 1e-3 : 0;
            lower[axis] = nudged(point[axis] - width, -static_cast<int>(spread == 0 ? 0 : rng() % 4));
            upper[axis] = nudged(point[axis] + width, static_cast<int>(spread == 0 ? 0 : rng() % 4));
        }
        const vec3<double> low{lower[0], lower[1], lower[2]}, high{upper[0], upper[1], upper[2]};
        const std::uint64_t exact_before = tally.exact;
        const bool fast = box_meets_sphere(low, high, centre, radius);
        settled += tally.exact == exact_before;
        ++total;
        meets += fast;
        ASSERT_EQ(fast, box_meets_sphere_reference(low, high, centre, radius))
            << "case " << i << ": box [" << hex(lower[0]) << " " << hex(lower[1]) << " " << hex(lower[2]) << "] .. ["
            << hex(upper[0]) << " " << hex(upper[1]) << " " << hex(upper[2]) << "], c " << hex(centre.x) << " "
            << hex(centre.y) << " " << hex(centre.z) << ", r " << hex(radius);
    }
    std::printf("%d of %d boxes meet the sphere; the filter settled %d\n", meets, total, settled);
    EXPECT_GT(meets, total / 10) << "the cases should straddle the surface";
    EXPECT_LT(meets, total * 9 / 10) << "the cases should straddle the surface";
    EXPECT_GT(settled, total / 2) << "the filter should settle most boxes";
    EXPECT_LT(settled, total) << "some boxes should need the exact route";
    // Outside the filter's range, and a box whose nearest point is exactly r away.
    EXPECT_EQ(box_meets_sphere({0x1p100, 0, 0}, {0x1p100, 0, 0}, {0, 0, 0}, 0x1p100), true);
    EXPECT_EQ(box_meets_sphere({0.5, 0, 0}, {1, 0, 0}, {0, 0, 0}, 1), true);
    EXPECT_EQ(box_meets_sphere({0.25, 0.25, 0.25}, {0.5, 0.5, 0.5}, {0, 0, 0}, 1), false);
}

// compare(|d|², x) against integer arithmetic: d = (m1, m2, m3)·2^k with
// m_i below 2^26, so |d|² = S·2^2k with S = m1² + m2² + m3² an exact integer
// below 2^54, against x the doubles around it (S itself where it is a
// double: a unit axis direction against 1 is one). Inside the filter range
// every comparison settles without big numbers, equal ones in expansions.
TEST(FastOracleSquaredLength, ComparesAsIntegerArithmeticDoes) {
    const std::uint64_t seed = 20261203;
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    stage_tally& tally = oracle_stage_counts_this_thread().comparisons;
    tally = {};
    // sign(S·2^2k − x) for x = X·2^e (X an integer of at most 53 bits), exactly.
    const auto expected = [](unsigned __int128 S, int k, double x) {
        int e = 0;
        const double fraction = std::frexp(x, &e);  // x = fraction·2^e, 0.5 ≤ fraction < 1
        const auto X = static_cast<unsigned __int128>(std::ldexp(fraction, 53));
        e -= 53;
        // Both sides as integers times 2^min(2k, e).
        const int low = std::min(2 * k, e);
        const unsigned __int128 left = S << (2 * k - low), right = X << (e - low);
        return left > right ? comparison::larger : left < right ? comparison::smaller : comparison::equal;
    };
    int equal = 0, total = 0;
    for (int i = 0; i < 20000; ++i) {
        const int bits = 1 + static_cast<int>(rng() % 26);
        const auto draw = [&] { return i % 7 == 0 ? 0 : static_cast<std::int64_t>(rng() % (std::uint64_t{1} << bits)); };
        const std::int64_t m[3] = {draw(), draw(), i % 5 == 0 ? std::int64_t{1} << (bits - 1) : draw()};
        const int k = static_cast<int>(rng() % 33) - 20;  // |d|² within 2^-40 .. 2^78: the filter range
        const vec3<double> d{std::ldexp(double(m[0]), k), std::ldexp(double(m[1]), k), std::ldexp(double(m[2]), k)};
        const unsigned __int128 S = static_cast<unsigned __int128>(m[0] * m[0]) + static_cast<unsigned __int128>(m[1] * m[1]) +
                                    static_cast<unsigned __int128>(m[2] * m[2]);
        if (S == 0) continue;
        const double nearest = std::ldexp(static_cast<double>(S), 2 * k);
        for (const double x : {nearest, std::nextafter(nearest, 0.0), std::nextafter(nearest, inf)}) {
            const comparison want = expected(S, k, x);
            equal += want == comparison::equal;
            ++total;
            ASSERT_EQ(compare_squared_length(d, x), want)
                << "case " << i << ": d " << hex(d.x) << " " << hex(d.y) << " " << hex(d.z) << ", x " << hex(x);
        }
    }
    std::printf("%d comparisons, %d equal\n", total, equal);
    EXPECT_GT(equal, total / 10);
    EXPECT_EQ(tally.exact, 0u) << "inside the filter range no comparison needs big numbers";
    EXPECT_GT(tally.expansion, 0u);
    EXPECT_EQ(compare_squared_length({0, 0, 1}, 1), comparison::equal);
    EXPECT_EQ(compare_squared_length({0, -1, 0}, 1), comparison::equal);
    // Outside the range, the exact route: 2^200 squared is 2^400.
    EXPECT_EQ(compare_squared_length({0x1p200, 0, 0}, 0x1p400), comparison::equal);
    EXPECT_GT(tally.exact, 0u);
}

// The lazily built exact state answers queries the enclosure cannot: the
// root itself (value == t*) and copies made before the first query.
TEST(FastOracleLazyState, CopiesAnswerAlike) {
    const exact_solution s = solve_exact({{0, 0, -5}, {0, 0, 3}, {0.5, 0, 0}, 1}, precision::binary64);
    ASSERT_EQ(s.stage, oracle_stage::filter);
    const exact_solution copy = s;
    const exact_solution ref = solve_exact_reference({{0, 0, -5}, {0, 0, 3}, {0.5, 0, 0}, 1}, precision::binary64);
    for (root_index i : {root_index::near_root, root_index::far_root}) {
        const double v = ref.root(i).rounded;
        EXPECT_TRUE(same_bits(s.root_ulp_error(i, v), ref.root_ulp_error(i, v)));
        EXPECT_TRUE(same_bits(copy.root_ulp_error(i, v), ref.root_ulp_error(i, v)));
        EXPECT_EQ(copy.compare_to_root(v, i), ref.compare_to_root(v, i));
    }
}

}  // namespace
}  // namespace rayverify
