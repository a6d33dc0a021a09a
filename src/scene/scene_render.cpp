#include "scene/scene_render.h"

#include <algorithm>
#include <cmath>

namespace rayverify {
namespace {

const rgb agree_exact = verdict_colour(verdict_kind::agree);
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
    const auto [r, g, b] = verdict_colour_rgb(v);
    return {r, g, b};
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

std::vector<scene_picture> scene_pictures_of(const scene& s) {
    std::vector<scene_picture> out = {scene_picture::exact, scene_picture::variant, scene_picture::difference_primary};
    if (s.shadow.enabled) out.push_back(scene_picture::difference_shadow);
    if (s.secondary.enabled) out.push_back(scene_picture::difference_secondary);
    return out;
}

std::string picture_file_name(scene_picture p) {
    switch (p) {
        case scene_picture::exact: return "exact.png";
        case scene_picture::variant: return "variant.png";
        case scene_picture::difference_primary: return "difference_primary.png";
        case scene_picture::difference_shadow: return "difference_shadow.png";
        case scene_picture::difference_secondary: return "difference_secondary.png";
    }
    return {};
}

scene_picture_builder::scene_picture_builder(const scene& s, std::size_t target_index, row_sink sink)
    : scene_(s),
      target_(target_index),
      sink_(std::move(sink)),
      pictures_(scene_pictures_of(s)),
      row_(static_cast<std::size_t>(s.camera.width)),
      rows_(pictures_.size(), std::vector<std::uint8_t>(static_cast<std::size_t>(s.camera.width) * 3)) {
    counts_.ramp_full_scale = std::ldexp(1.0, significand_bits(s.prec) / 2);
    for (scene_picture p : pictures_)
        if (p >= scene_picture::difference_primary)
            counts_.kind_drawn[static_cast<std::size_t>(p) - static_cast<std::size_t>(scene_picture::difference_primary)] =
                true;
}

void scene_picture_builder::add(const judged_ray& j) {
    const scene_ray& r = *j.ray;
    if (r.y != row_y_) send_rows_before(r.y);
    pixel_state& p = row_[static_cast<std::size_t>(r.x)];
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

rgb scene_picture_builder::variant_colour(const pixel_state& p, double light) const {
    if (!p.variant->hit || p.variant->sphere < 0) return agree_miss;
    const scene_sphere& s = scene_.spheres[static_cast<std::size_t>(p.variant->sphere)];
    const vec3<double> point = p.origin + p.variant->t * p.direction;
    const vec3<double> n = point - s.centre;
    const double len = std::sqrt(length_squared(n));
    return len > 0 ? normal_colour({n.x / len, n.y / len, n.z / len}, light) : rgb{255, 255, 255};
}

void scene_picture_builder::send_rows_before(int y) {
    const int end = std::min(y, scene_.camera.height);
    for (; row_y_ < end; ++row_y_) {
        for (std::size_t x = 0; x < row_.size(); ++x) {
            const pixel_state& p = row_[x];
            const auto put = [&](std::size_t picture, rgb c) {
                rows_[picture][3 * x] = c.r;
                rows_[picture][3 * x + 1] = c.g;
                rows_[picture][3 * x + 2] = c.b;
            };
            for (std::size_t i = 0; i < pictures_.size(); ++i) put(i, not_cast);
            if (!p.cast) continue;
            // Exact and variant renders: a lit fraction darkens occluded light.
            const auto light = [&](int shadowed) {
                return p.lights == 0 ? 1.0 : 0.35 + 0.65 * (p.lights - shadowed) / p.lights;
            };
            for (std::size_t i = 0; i < pictures_.size(); ++i) {
                switch (pictures_[i]) {
                    case scene_picture::exact:
                        put(i, p.exact->hit ? normal_colour(p.exact->normal, light(p.exact_shadowed)) : agree_miss);
                        break;
                    case scene_picture::variant: put(i, variant_colour(p, light(p.variant_shadowed))); break;
                    default: {
                        const std::size_t k = static_cast<std::size_t>(pictures_[i]) -
                                              static_cast<std::size_t>(scene_picture::difference_primary);
                        if (!p.verdict[k]) break;
                        const verdict_kind verdict = *p.verdict[k];
                        ++counts_.pixels_by_verdict[k][static_cast<std::size_t>(verdict)];
                        rgb c = verdict_colour(verdict);
                        if (verdict == verdict_kind::agree)
                            c = !p.hit[k] ? agree_miss
                                : p.ulp[k] ? ulp_colour(*p.ulp[k], counts_.ramp_full_scale)
                                           : agree_exact;
                        put(i, c);
                    }
                }
            }
        }
        sink_(row_y_, rows_);
        std::fill(row_.begin(), row_.end(), pixel_state{});
    }
}

scene_picture_counts scene_picture_builder::finish() {
    send_rows_before(scene_.camera.height);
    return counts_;
}

}  // namespace rayverify
