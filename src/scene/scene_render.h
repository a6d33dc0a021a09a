// Pictures of a scene audit: RGB rows drawn from judged rays, one row of
// pixels at a time (the CLI encodes them as PNG with report/png_image.h).
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
#include <functional>
#include <optional>
#include <span>
#include <string>
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

// The pictures of a render, in the order they are written: the exact and the
// variant's render, then a difference picture per ray kind the scene casts.
enum class scene_picture { exact, variant, difference_primary, difference_shadow, difference_secondary };
std::vector<scene_picture> scene_pictures_of(const scene& s);
std::string picture_file_name(scene_picture p);  // "exact.png", "difference_shadow.png", …

struct scene_picture_counts {
    std::array<bool, 3> kind_drawn{};  // by ray_kind: a difference picture is drawn
    // Pixels of each kind by verdict (a pixel with several shadow rays takes the first disagreement).
    std::array<std::array<std::size_t, verdict_kind_count>, 3> pixels_by_verdict{};
    // The ULP error at which the ramp saturates: 2^(p/2) in the scene's precision.
    double ramp_full_scale = 0;
};

// Draws the pictures from judged rays for one target, given in the order
// audit_scene gives them (raster order), holding one row of pixels: each
// finished row goes to the sink — its y, then one RGB row per picture of
// scene_pictures_of (width × 3 bytes) — rows 0 … height − 1 in order.
class scene_picture_builder {
public:
    using row_sink = std::function<void(int y, std::span<const std::vector<std::uint8_t>> rows)>;
    scene_picture_builder(const scene& s, std::size_t target_index, row_sink sink);
    void add(const judged_ray& r);
    // Sends the rows not sent yet; the counts of the whole picture.
    scene_picture_counts finish();

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
    void send_rows_before(int y);  // rows up to y − 1 are complete
    rgb variant_colour(const pixel_state& p, double light) const;

    const scene& scene_;
    std::size_t target_;
    row_sink sink_;
    std::vector<scene_picture> pictures_;
    int row_y_ = 0;                    // the row being collected
    std::vector<pixel_state> row_;     // its pixels
    std::vector<std::vector<std::uint8_t>> rows_;  // one RGB row per picture
    scene_picture_counts counts_;
};

}  // namespace rayverify
