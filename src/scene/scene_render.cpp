#include "scene/scene_render.h"

#include <algorithm>
#include <cmath>

namespace rayverify {
namespace {

constexpr rgb agree_exact{50, 50, 50};
constexpr rgb agree_max{255, 230, 0};
constexpr rgb agree_miss{0, 0, 0};
constexpr rgb not_cast{30, 30, 70};

rgb lerp(rgb a, rgb b, double t) {
    const auto mix = [t](std::uint8_t x, std::uint8_t y) {
        return static_cast<std::uint8_t>(std::lround(x + (y - x) * t));
    };
    return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

// Normal shading: (n + 1)/2 per channel, scaled by `light` in [0, 1].
rgb normal_colour(vec3<double> n, double light) {
    const auto channel = [light](double v) {
        return static_cast<std::uint8_t>(std::lround(std::clamp((v + 1) / 2, 0.0, 1.0) * 255 * light));
    };
    return {channel(n.x), channel(n.y), channel(n.z)};
}

// Where on the ramp an agreeing hit's ULP error sits: log2(1 + ulp) against
// log2(1 + full scale).
rgb ulp_colour(double ulp, double full_scale) {
    const double t = std::clamp(std::log2(1 + ulp) / std::log2(1 + full_scale), 0.0, 1.0);
    return lerp(agree_exact, agree_max, t);
}

}  // namespace

rgb verdict_colour(verdict_kind v) {
    switch (v) {
        case verdict_kind::agree: return agree_exact;
        case verdict_kind::false_miss: return {230, 30, 30};
        case verdict_kind::false_hit: return {40, 110, 255};
        case verdict_kind::tangent_split: return {255, 230, 0};
        case verdict_kind::tangent_missed: return {150, 0, 40};
        case verdict_kind::false_tangent: return {180, 170, 90};
        case verdict_kind::wrong_root: return {255, 140, 0};
        case verdict_kind::wrong_sphere: return {40, 200, 40};
        case verdict_kind::wrong_side: return {255, 0, 255};
        case verdict_kind::non_finite: return {255, 255, 255};
        case verdict_kind::malformed_output: return {0, 220, 220};
        case verdict_kind::contract_violation: return {90, 90, 90};
        case verdict_kind::invalid: return {60, 60, 60};
    }
    return {};
}

std::vector<palette_entry> scene_palette() {
    std::vector<palette_entry> p;
    for (int i = 1; i < verdict_kind_count; ++i) {
        const auto v = static_cast<verdict_kind>(i);
        p.push_back({verdict_name(v), verdict_colour(v), verdict_meaning(v)});
    }
    p.push_back({"agree_hit_exact", agree_exact, "agrees; nearest root error 0 ulp (the start of the ULP ramp)"});
    p.push_back({"agree_hit_max", agree_max,
                 "agrees; ULP error ≥ the full scale (log2(1 + ulp) ramp from agree_hit_exact)"});
    p.push_back({"agree_miss", agree_miss, "agrees: no hit"});
    p.push_back({"not_cast", not_cast, "pixel not sampled, or no ray of this kind (no exact primary hit)"});
    return p;
}

rgb_image::rgb_image(int w, int h, rgb fill) : width(w), height(h) {
    pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) set(x, y, fill);
}

void rgb_image::set(int x, int y, rgb c) {
    const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
    pixels[i] = c.r;
    pixels[i + 1] = c.g;
    pixels[i + 2] = c.b;
}

rgb rgb_image::at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
    return {pixels[i], pixels[i + 1], pixels[i + 2]};
}

scene_picture_builder::scene_picture_builder(const scene& s, std::size_t target_index)
    : scene_(s),
      target_(target_index),
      pixels_(static_cast<std::size_t>(s.camera.width) * static_cast<std::size_t>(s.camera.height)) {}

void scene_picture_builder::add(const judged_ray& j) {
    const scene_ray& r = *j.ray;
    pixel_state& p = pixels_[static_cast<std::size_t>(r.y) * static_cast<std::size_t>(scene_.camera.width) +
                             static_cast<std::size_t>(r.x)];
    const std::size_t kind = static_cast<std::size_t>(r.kind);
    const variant_ray_answer& answer = j.answers.at(target_);
    if (r.kind == ray_kind::primary) {
        p.cast = true;
        p.exact = j.exact;
        p.variant = answer;
        p.origin = r.origin;
        p.direction = r.direction;
    } else if (r.kind == ray_kind::shadow) {
        ++p.lights;
        p.exact_shadowed += j.exact.hit ? 1 : 0;
        p.variant_shadowed += answer.hit ? 1 : 0;
    }
    p.hit[kind] = p.hit[kind] || j.exact.hit;
    if (!p.verdict[kind] || *p.verdict[kind] == verdict_kind::agree) p.verdict[kind] = answer.verdict;
    if (answer.nearest_ulp) p.ulp[kind] = std::max(p.ulp[kind].value_or(0.0), *answer.nearest_ulp);
}

scene_pictures scene_picture_builder::finish() const {
    const int w = scene_.camera.width, h = scene_.camera.height;
    scene_pictures out{rgb_image(w, h, not_cast), rgb_image(w, h, not_cast), {}, {}, 0};
    out.ramp_full_scale = std::ldexp(1.0, significand_bits(scene_.prec) / 2);
    const std::array<bool, 3> casts = {true, scene_.shadow.enabled, scene_.secondary.enabled};
    for (std::size_t k = 0; k < 3; ++k)
        if (casts[k]) out.difference[k] = rgb_image(w, h, not_cast);

    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const pixel_state& p = pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                           static_cast<std::size_t>(x)];
            if (!p.cast) continue;
            // Exact and variant renders: a lit fraction darkens occluded light.
            const auto light = [&](int shadowed) {
                return p.lights == 0 ? 1.0 : 0.35 + 0.65 * (p.lights - shadowed) / p.lights;
            };
            out.exact.set(x, y, p.exact->hit ? normal_colour(p.exact->normal, light(p.exact_shadowed)) : agree_miss);
            rgb v = agree_miss;
            if (p.variant->hit && p.variant->sphere >= 0) {
                const scene_sphere& s = scene_.spheres[static_cast<std::size_t>(p.variant->sphere)];
                const vec3<double> point = p.origin + p.variant->t * p.direction;
                const vec3<double> n = point - s.centre;
                const double len = std::sqrt(length_squared(n));
                v = len > 0 ? normal_colour({n.x / len, n.y / len, n.z / len}, light(p.variant_shadowed))
                            : rgb{255, 255, 255};
            }
            out.variant.set(x, y, v);

            for (std::size_t k = 0; k < 3; ++k) {
                if (!out.difference[k] || !p.verdict[k]) continue;
                const verdict_kind verdict = *p.verdict[k];
                ++out.pixels_by_verdict[k][static_cast<std::size_t>(verdict)];
                rgb c = verdict_colour(verdict);
                if (verdict == verdict_kind::agree)
                    c = !p.hit[k] ? agree_miss : p.ulp[k] ? ulp_colour(*p.ulp[k], out.ramp_full_scale) : agree_exact;
                out.difference[k]->set(x, y, c);
            }
        }
    }
    return out;
}

}  // namespace rayverify
