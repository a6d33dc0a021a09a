// Pictures of a scene audit: RGB pixel buffers built from judged rays (the
// CLI writes them as PNG with report/png_image.h).
//   exact    — each pixel's exact nearest hit shaded by its normal (colour =
//              (n + 1)/2), darkened where exact shadow rays find an occluder;
//   variant  — the same from one variant's answers (normal at o + t·d for the
//              variant's t on the sphere it reports);
//   difference, one per ray kind the scene casts — each pixel coloured by the
//              verdict of its ray(s) of that kind (scene_palette), agreeing
//              hits shaded by the ULP error of the nearest root.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "scene/scene.h"
#include "scene/scene_audit.h"

namespace rayverify {

struct rgb {
    std::uint8_t r = 0, g = 0, b = 0;
};

// The colours of the difference images, with what each means.
struct palette_entry {
    std::string_view name;
    rgb colour;
    std::string_view meaning;
};
// One entry per verdict_kind except agree (in verdict order), then:
// "agree_hit_exact" and "agree_hit_max" (the ends of the ULP ramp),
// "agree_miss" and "not_cast".
std::vector<palette_entry> scene_palette();
rgb verdict_colour(verdict_kind v);

struct rgb_image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels;  // row by row from the top, 3 bytes a pixel
    rgb_image(int w, int h, rgb fill);
    void set(int x, int y, rgb c);
    rgb at(int x, int y) const;
};

struct scene_pictures {
    rgb_image exact;
    rgb_image variant;
    std::array<std::optional<rgb_image>, 3> difference;  // by ray_kind; present for kinds the scene casts
    // Pixels of each kind by verdict (a pixel with several shadow rays takes the first disagreement).
    std::array<std::array<std::size_t, verdict_kind_count>, 3> pixels_by_verdict{};
    // The ULP error at which the ramp saturates: 2^(p/2) in the scene's precision.
    double ramp_full_scale = 0;
};

// Collects judged rays (in the order audit_scene gives them) for one target.
class scene_picture_builder {
public:
    scene_picture_builder(const scene& s, std::size_t target_index);
    void add(const judged_ray& r);
    scene_pictures finish() const;

private:
    struct pixel_state {
        bool cast = false;
        std::optional<exact_ray_answer> exact;
        std::optional<variant_ray_answer> variant;
        vec3<double> origin, direction;
        int lights = 0, exact_shadowed = 0, variant_shadowed = 0;
        std::array<std::optional<verdict_kind>, 3> verdict;  // first disagreement (or agree) per kind
        std::array<std::optional<double>, 3> ulp;             // nearest-root ULP when agreeing
        std::array<bool, 3> hit{};                            // exact hit, per kind
    };
    const scene& scene_;
    std::size_t target_;
    std::vector<pixel_state> pixels_;
};

}  // namespace rayverify
