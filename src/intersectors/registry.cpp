#include "intersectors/registry.h"

#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>

#include "intersectors/cycles_point.h"
#include "intersectors/embree4_sphere.h"
#include "intersectors/fma_discriminant.h"
#include "intersectors/geometric.h"
#include "intersectors/half_b.h"
#include "intersectors/hearn_baker.h"
#include "intersectors/hearn_baker_any_hit.h"
#include "intersectors/hearn_baker_nearest.h"
#include "intersectors/hearn_baker_unit.h"
#include "intersectors/godot_segment.h"
#include "intersectors/jolt_ray_sphere.h"
#include "intersectors/mitsuba3_sphere.h"
#include "intersectors/naive.h"
#include "intersectors/pbrt_v4_sphere.h"
#include "intersectors/raylib_collision.h"
#include "intersectors/robust.h"
#include "intersectors/seed003_reduced.h"
#include "intersectors/seed004_early_out.h"
#include "intersectors/stable_roots.h"
#include "intersectors/threejs_ray.h"
#include "intersectors/wald_origin_shift.h"

namespace rayverify {
namespace {

#define RAYVERIFY_BOTH_PRECISIONS(fn) &intersectors::fn<float>, &intersectors::fn<double>

// A kind that takes an interval: run_float_in/run_double_in answer for the
// interval given, run_float/run_double for the default (0, +inf).
template <class T>
using interval_fn = root_pair<T> (*)(const ray_sphere<T>&, T, T);

template <interval_fn<float> F, interval_fn<double> D>
variant interval_variant(std::string name, std::string citation, std::string formula, contract promises) {
    variant v{std::move(name), std::move(citation), std::move(formula), promises,
              [](const ray_sphere<float>& s) { return F(s, 0.0f, std::numeric_limits<float>::infinity()); },
              [](const ray_sphere<double>& s) { return D(s, 0.0, std::numeric_limits<double>::infinity()); }};
    v.run_float_in = F;
    v.run_double_in = D;
    return v;
}

// An engine's port: its function takes (s, tmin, tmax) (the interval is
// ignored by a fixed-range contract) and returns roots or a whole answer, in
// float, double or both (nullptr: the engine has no such build).
template <class T>
using answer_fn = answer<T> (*)(const ray_sphere<T>&, T, T);

template <class T, class Fn>
void bind_engine(variant& v, Fn fn) {
    constexpr T inf = std::numeric_limits<T>::infinity();
    const auto roots = [fn](const ray_sphere<T>& s, T tmin, T tmax) {
        if constexpr (std::is_same_v<decltype(fn(s, tmin, tmax)), answer<T>>)
            return fn(s, tmin, tmax).roots;
        else
            return fn(s, tmin, tmax);
    };
    const auto plain = [roots](const ray_sphere<T>& s) { return roots(s, T(0), inf); };
    const bool interval = takes_interval(v.promises);
    if constexpr (std::is_same_v<T, float>) {
        v.run_float = plain;
        if (interval) v.run_float_in = roots;
        if constexpr (std::is_same_v<Fn, answer_fn<float>>) v.answer_float = fn;
    } else {
        v.run_double = plain;
        if (interval) v.run_double_in = roots;
        if constexpr (std::is_same_v<Fn, answer_fn<double>>) v.answer_double = fn;
    }
}

template <class FloatFn, class DoubleFn>
variant engine_variant(std::string name, std::string citation, std::string formula, contract promises,
                       std::string build, FloatFn f, DoubleFn d) {
    variant v;
    v.name = std::move(name);
    v.citation = std::move(citation);
    v.formula = std::move(formula);
    v.promises = promises;
    v.build = std::move(build);
    if constexpr (!std::is_same_v<FloatFn, std::nullptr_t>) bind_engine<float>(v, f);
    if constexpr (!std::is_same_v<DoubleFn, std::nullptr_t>) bind_engine<double>(v, d);
    return v;
}

#define RAYVERIFY_INTERVAL_VARIANT(fn, citation, formula) \
    interval_variant<&intersectors::fn<float>, &intersectors::fn<double>>(#fn, citation, formula, intersectors::fn##_contract)

// The robust variants decide exactly by construction (robust_sphere.h).
variant with_exact_decisions(variant v) {
    v.exact_decisions = true;
    return v;
}

// Its size follows from the list.
const auto registry = std::to_array<variant>({
    {"naive", "seed 000 / seed 001 (textbook quadratic)",
     "b = 2d·f, C = f·f − r², Δ = b² − 4aC, t = (−b ∓ √Δ)/2a", intersectors::naive_contract,
     RAYVERIFY_BOTH_PRECISIONS(naive)},
    {"half_b", "Ray Tracing in One Weekend §6.2",
     "h = d·(c − o), Δ = h² − aC, t = (h ∓ √Δ)/a", intersectors::half_b_contract,
     RAYVERIFY_BOTH_PRECISIONS(half_b)},
    {"seed003_reduced", "seed 003 (GLM-style reduced quadratic, as published)",
     "p = d̂·f, q = f·f − r², Δ = p² − q, t = −p ∓ √Δ, tangent if Δ ≤ 1e-7",
     intersectors::seed003_reduced_contract, RAYVERIFY_BOTH_PRECISIONS(seed003_reduced)},
    {"seed004_early_out", "seed 004 (DirectX RayToSphere, as published)",
     "b = f·d̂, C = f·f − r², miss if C > 0 ∧ b > 0, t = max(0, −b − √(b² − C))",
     intersectors::seed004_early_out_contract, RAYVERIFY_BOTH_PRECISIONS(seed004_early_out)},
    {"geometric", "seed 000 closest approach (three.js, PhysX)",
     "t_ca = (c − o)·d̂, d² = |c − o|² − t_ca², miss if d² > r², t = t_ca ∓ √(r² − d²)",
     intersectors::geometric_contract, RAYVERIFY_BOTH_PRECISIONS(geometric)},
    {"stable_roots", "Numerical Recipes §5.6; RTG ch.7 method 1",
     "q = −½(b + sign(b)√Δ), t = q/a, C/q", intersectors::stable_roots_contract,
     RAYVERIFY_BOTH_PRECISIONS(stable_roots)},
    {"hearn_baker", "Ray Tracing Gems ch.7 final form (Hearn–Baker Δ + stable roots)",
     "b′ = −f·d, Δ = r² − |f + (b′/a)d|², q = b′ + sign(b′)√(aΔ), t = C/q, q/a",
     intersectors::hearn_baker_contract, RAYVERIFY_BOTH_PRECISIONS(hearn_baker)},
    {"fma_discriminant", "naive with Kahan's FMA difference of products (pbrt-v4)",
     "Δ = DifferenceOfProducts(b, b, 4a, C), t = (−b ∓ √Δ)/2a",
     intersectors::fma_discriminant_contract, RAYVERIFY_BOTH_PRECISIONS(fma_discriminant)},
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_any_hit,
                               "Ray Tracing Gems ch.7 final form, any-hit in (tmin, tmax) (shadow rays)",
                               "miss if C > 0 ∧ b′ < 0 ∧ tmin ≥ 0; hit if C < 0 ∧ (tmin, tmax) ⊇ (0, ∞); "
                               "Δ = r² − |f + (b′/a)d|²; then only the roots the answer needs, C/q and q/a"),
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_nearest, "Ray Tracing Gems ch.7 final form, nearest root in (tmin, tmax)",
                               "Δ = r² − |f + (b′/a)d|², q = b′ + sign(b′)√(aΔ); near C/q if C > 0 ∧ b′ > 0, "
                               "far q/a only if needed"),
    {"hearn_baker_unit", "Ray Tracing Gems ch.7 final form with a = d·d = 1",
     "b′ = −f·d̂, Δ = r² − |f + b′d̂|², q = b′ + sign(b′)√Δ, t = C/q, q",
     intersectors::hearn_baker_unit_contract, RAYVERIFY_BOTH_PRECISIONS(hearn_baker_unit)},
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_unit_nearest,
                               "Ray Tracing Gems ch.7 final form with a = 1, nearest root in (tmin, tmax)",
                               "Δ = r² − |f + b′d̂|², q = b′ + sign(b′)√Δ; near C/q if C > 0 ∧ b′ > 0, "
                               "far q only if needed"),
    RAYVERIFY_INTERVAL_VARIANT(hearn_baker_unit_any_hit,
                               "Ray Tracing Gems ch.7 final form with a = 1, any-hit in (tmin, tmax) (shadow rays)",
                               "as hearn_baker_any_hit with a = 1: Δ = r² − |f + b′d̂|², roots C/q and q only as needed"),
    {"wald_origin_shift", "Ray Tracing Gems II ch.34 (Wald): origin shift, then the textbook quadratic",
     "t_s = (c − o)·d/(d·d), o′ = o + t_s·d, then naive from o′: t = t_s + (−b ∓ √Δ)/2a",
     intersectors::wald_origin_shift_contract, RAYVERIFY_BOTH_PRECISIONS(wald_origin_shift)},
    with_exact_decisions(
        {"robust", "rayverify robust_sphere.h (certified double/double-word filter, Shewchuk expansions)",
         "sign of Δ′ = a·r² − |d × f|², C, b′ exact; q = −(b′ + sign(b′)√Δ′), t = q/a, C/q rounded to nearest",
         intersectors::robust_contract, RAYVERIFY_BOTH_PRECISIONS(robust)}),
    with_exact_decisions(RAYVERIFY_INTERVAL_VARIANT(
        robust_nearest, "rayverify robust_sphere.h, nearest root in (tmin, tmax)",
        "as robust; the roots' comparisons with tmin and tmax exact, only the roots needed")),
    with_exact_decisions(RAYVERIFY_INTERVAL_VARIANT(
        robust_any_hit, "rayverify robust_sphere.h, any root in (tmin, tmax) (shadow rays)",
        "as robust_nearest, answering only whether a root lies in the interval")),
    with_exact_decisions(
        {"robust_bounded", "rayverify robust_sphere.h, bounded tier (roots::bounded)",
         "as robust; double roots q/a and C/q from the static filter, within 2^-44 relative (float: as robust)",
         intersectors::robust_bounded_contract, RAYVERIFY_BOTH_PRECISIONS(robust_bounded)}),
    with_exact_decisions(RAYVERIFY_INTERVAL_VARIANT(
        robust_bounded_nearest, "rayverify robust_sphere.h, bounded tier, nearest root in (tmin, tmax)",
        "as robust_nearest; double roots within 2^-44 relative (float: as robust_nearest)")),
    // Engines, as published (each header cites its source and states the build it models).
    engine_variant("pbrt_v4", "pbrt-v4 Sphere::BasicIntersect (src/pbrt/shapes.h, mmp/pbrt-v4 5f7a6068)",
                   "interval arithmetic: a, b, c, v = o − (b/2a)d, Δ = 4a(r + |v|)(r − |v|), q = −½(b ± √Δ), "
                   "t0 = q/a, t1 = c/q; the interval midpoint, reprojected hit point and its error bound",
                   intersectors::pbrt_v4_contract,
                   "Float = float (default) and PBRT_FLOAT_AS_DOUBLE; x86-64 CPU build, no -march (no FMA: std::fma only "
                   "in DifferenceOfProducts, unused here; no FMA instruction to contract into), divisions IEEE; CPU rounding "
                   "helpers (NextFloatUp/Down of the rounded result); sphere at c through Translate(c); atan2 from the "
                   "host libm",
                   &intersectors::pbrt_v4<float>, &intersectors::pbrt_v4<double>),
    engine_variant("mitsuba3_preliminary",
                   "Mitsuba 3 Sphere::ray_intersect_preliminary_impl (src/shapes/sphere.cpp, v3.9.1-12-gb45b0a93)",
                   "plane_t = dot(−l, d)/|d|, o′ = fmadd(d, plane_t, o) − c, solve_quadratic(|d|², 2o′·d, |o′|² − r²) "
                   "with an FMA discriminant, t = plane_t + near (far when near < 0)",
                   intersectors::mitsuba3_preliminary_contract,
                   "scalar_rgb (float rays, double arithmetic, t rounded to float) and scalar_rgb_double; x86-64 "
                   "AVX+FMA: fused fmadd/fmsub, 3-double dot summed y + (z + x); clang (no other fusion); "
                   "divisions and √ IEEE (no reciprocal estimate)",
                   &intersectors::mitsuba3_preliminary<float>, &intersectors::mitsuba3_preliminary<double>),
    engine_variant("mitsuba3_ray_test", "Mitsuba 3 Sphere::ray_test_impl (shadow rays; src/shapes/sphere.cpp, v3.9.1)",
                   "o′ = o − c (no shift), solve_quadratic(|d|², 2o′·d, |o′|² − r²), hit when a root lies in [0, maxt]",
                   intersectors::mitsuba3_ray_test_contract,
                   "as mitsuba3_preliminary: scalar_rgb (float rays, double arithmetic) and scalar_rgb_double; x86-64 "
                   "AVX+FMA, fused fmsub in the discriminant; clang; divisions IEEE",
                   &intersectors::mitsuba3_ray_test<float>, &intersectors::mitsuba3_ray_test<double>),
    engine_variant("embree4", "Embree 4 SphereIntersector1 (kernels/geometry/sphere_intersector.h, v4.4.1-8-g93040c7a)",
                   "rd2 = rcp(d·d), projC0 = (c − o)·d·rd2, perp = c0 − projC0·d, td = √((r² − |perp|²)·rd2), "
                   "t = projC0 ∓ td, first in [tnear, tfar]; Ng = ∓td·d − perp",
                   intersectors::embree4_contract,
                   "float only; Embree 4 for aarch64 (NEON, sse2neon), clang -ffp-contract=on, FPCR round to "
                   "nearest, FZ = 0: d·d = (x·x + y·y) + z·z (no FMA), rcp = vrecpe estimate (FRECPE, "
                   "architecturally exact) + two vrecps Newton steps, other dots fused madd(x, x′, madd(y, y′, z·z′)); "
                   "x86's rcpss/rcp14 estimate differs between CPUs and is not modelled",
                   &intersectors::embree4<float>, nullptr),
    engine_variant("cycles_point", "Blender Cycles point_intersect_test (src/kernel/geom/point_intersect.h, v5.0.0-435)",
                   "Embree's formula, front face only: t_front = projC0 − td in [tmin, tmax], else miss",
                   intersectors::cycles_point_contract,
                   "float only; x86-64 SSE4.2 kernel: dot = _mm_dp_ps ((x + y) + z), no FMA; rd2 = 1.0f/(d·d), an "
                   "IEEE division (no rcp estimate)",
                   &intersectors::cycles_point<float>, nullptr),
    engine_variant("jolt", "Jolt Physics RaySphere + FindRoot (Jolt/Geometry/RaySphere.h, v5.5.0-182-g3b47ec39)",
                   "a = |d|², b = 2d·f, C = |f|² − r², det = b² − 4aC, q = (b + sign(b)√det)/−2, roots q/a, C/q; "
                   "inside: 0; a fraction of the direction",
                   intersectors::jolt_contract,
                   "float only; x86-64 JPH_CROSS_PLATFORM_DETERMINISTIC: no JPH_USE_FMADD, -ffp-contract=off, no "
                   "FMA anywhere; SSE4.1 dot (x + y) + (z + 0); called with origin o + tmin·d and direction d "
                   "(no tmax: unbounded, fraction = t − tmin) or (tmax − tmin)·d (a segment, fraction < 1 + FLT_EPSILON)",
                   &intersectors::jolt<float>, nullptr),
    engine_variant("jolt_fma", "Jolt Physics RaySphere + FindRoot (Jolt/Geometry/RaySphere.h, v5.5.0-182-g3b47ec39)",
                   "as jolt, det = DifferenceOfProducts(b, b, 4a, C) with FMA (Kahan), C = fma(−r, r, |f|²)",
                   intersectors::jolt_fma_contract,
                   "float only; the default x86-64 build: USE_AVX2 + JPH_USE_FMADD, -mfma, -ffp-contract=fast: "
                   "DifferenceOfProducts fused as Math.h writes it, C's r² contracted into an FMA by the compiler "
                   "(std::fma here), SSE4.1 dot (x + y) + z; called as jolt",
                   &intersectors::jolt_fma<float>, nullptr),
    engine_variant("threejs", "three.js Ray.intersectSphere (src/math/Ray.js)",
                   "v = c − o, tca = v·d, d2 = v·v − tca², thc = √(r² − d2), point o + d·(tca ∓ thc)",
                   intersectors::threejs_contract, "double only (JavaScript numbers: IEEE double on any engine and CPU, never fused or reordered)",
                   nullptr, &intersectors::threejs<double>),
    engine_variant("godot", "Godot Geometry3D::segment_intersects_sphere (core/math/geometry_3d.cpp, 4.x)",
                   "n = rel/|rel|, s = n·(c − from), dist = |n·s − (c − from)|, t = s − √(r² − dist²) "
                   "(not when r² − dist² < 1e-5), point from + n·t, normal",
                   intersectors::godot_contract,
                   "real_t = float (default) and double (precision=double); x86-64 baseline (SSE2), no FMA, divisions and "
                   "√ IEEE; segment from o + tmin·d to o + tmax·d, or without tmax to o + L·d (L = segment_length: a power "
                   "of two, L·|d|∞ ≥ 2(|o − c|₁ + r)); t of the point = (p − o)·d/(d·d) (parameter_of_point)",
                   &intersectors::godot<float>, &intersectors::godot<double>),
    engine_variant("raylib", "raylib GetRayCollisionSphere (src/rmodels.c, 6.0-322-gabe23bf8)",
                   "v = c − o, b = v·d, disc = r² − (|v|² − b²), t = b ∓ √disc (+ inside), point o + d·t, normal",
                   intersectors::raylib_contract, "float only; C, x86-64 baseline (SSE2, no FMA); sqrtf; 1.0f/length an IEEE division",
                   &intersectors::raylib<float>, nullptr),
});

#undef RAYVERIFY_INTERVAL_VARIANT

#undef RAYVERIFY_BOTH_PRECISIONS

}  // namespace

std::span<const variant> builtin_variants() { return registry; }

const variant* find_builtin_variant(std::string_view name) {
    for (const variant& v : registry)
        if (v.name == name) return &v;
    return nullptr;
}

}  // namespace rayverify
