// A renderer's scene: the spheres, the camera, the rays the renderer casts
// and the query each ray needs. `read_scene` parses the JSON scene format
// (documented in corpus/scenes/README.md); `for_each_ray` produces exactly the
// rays the renderer would cast, each of which meets each sphere as one
// `corpus_case` that the oracle and the variants judge like any other.
//
// Hit points that spawn shadow and secondary rays come from the exact oracle:
// the correctly rounded (in the scene's precision) hit point of the exact
// nearest hit. Every variant is therefore audited on the same rays, and a
// variant's error on the primary ray does not move the rays that follow it.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/intersection.h"
#include "core/ray_sphere_case.h"
#include "core/vec3.h"
#include "oracle/oracle.h"

namespace rayverify {

struct scene_sphere {
    std::string name;  // "sphere<i>" when the file gives none
    vec3<double> centre;
    double radius = 1;
};

enum class projection { perspective, orthographic };

// A pinhole camera at `position` looking at `look_at`, `up` fixing the roll.
// Pixel (x, y), x to the right, y down, is sampled at its centre.
// Perspective: every ray starts at `position`; the image plane at distance 1
// spans tan(fov/2) vertically either side of the axis (fov is vertical, in
// degrees). Orthographic: every ray has the view direction and starts on the
// plane through `position`, offset by the pixel's position on a view of
// `view_height` world units (width in proportion to the resolution).
struct scene_camera {
    projection kind = projection::perspective;
    vec3<double> position{0, 0, 0};
    vec3<double> look_at{0, 0, -1};
    vec3<double> up{0, 1, 0};
    double fov_degrees = 60;  // perspective
    double view_height = 2;   // orthographic
    int width = 64;
    int height = 48;
};

// A point light; each primary hit casts one shadow ray towards each light.
struct scene_light {
    std::string name;
    vec3<double> position;
};

// How a renderer keeps a ray spawned at a hit point P from finding the
// surface it starts on: move the origin by `offset` = absolute +
// relative·|P| (along the outward normal at P, or along the new ray's
// direction), and/or start the ray's interval at tmin. Or an engine's own
// rule, in the scene's precision (absolute and relative unused):
//   pbrt_v4   OffsetRayOrigin (src/pbrt/ray.h): P's error bound as pbrt-v4 has it at a
//             sphere hit (γ₅·|P − c| in object space, carried to render space by
//             Translate(c)), offset along n by |n|·error, to the side the ray leaves to,
//             each coordinate then rounded one float step further away
//   mitsuba3  Interaction::offset_p (include/mitsuba/render/interaction.h): along n by
//             (1 + max|P_k|)·RayEpsilon, RayEpsilon = 1500·2^−24, signed by n·d, with an FMA
enum class offset_rule { none, along_normal, along_ray, pbrt_v4, mitsuba3 };

struct spawn_settings {
    offset_rule rule = offset_rule::none;
    double absolute = 0;
    double relative = 0;  // times |P| (the VisRTX rule is relative = 1e-6)
    double tmin = 0;      // the new ray's interval starts here (the "ray epsilon")
};

// Which secondary ray a primary hit spawns: the mirror reflection about the
// normal, or the primary direction continued through the surface (the ray
// that finds the exit point or a nested sphere).
enum class secondary_direction { reflect, transmit };

// The kinds of ray a renderer casts: from the camera, towards a light, and
// the one a primary hit spawns.
enum class ray_kind { primary, shadow, secondary };
inline constexpr std::array every_ray_kind{ray_kind::primary, ray_kind::shadow, ray_kind::secondary};
const char* ray_kind_name(ray_kind k);

struct ray_kind_settings {
    bool enabled = false;
    ray_query query = ray_query::nearest_hit;
};

// Which pixels are cast: all, or `count` distinct pixels drawn with `seed`
// (std::mt19937_64, partial Fisher–Yates), cast in raster order.
struct pixel_sample {
    bool all = true;
    std::size_t count = 0;
    std::uint64_t seed = 0;
};

struct scene {
    std::string name;     // the file's stem
    std::string comment;  // what the scene shows and which anchor it reproduces
    std::filesystem::path file;
    precision prec = precision::binary64;
    bool normalise_directions = false;  // directions are d/|d| computed in prec
    std::vector<scene_sphere> spheres;
    scene_camera camera;
    std::vector<scene_light> lights;
    ray_kind_settings primary{true, ray_query::nearest_hit};
    double primary_tmin = 0;  // primary rays take roots in (primary_tmin, ∞)
    ray_kind_settings shadow{false, ray_query::any_hit};
    spawn_settings shadow_spawn;
    ray_kind_settings secondary{false, ray_query::nearest_hit};
    spawn_settings secondary_spawn;
    secondary_direction secondary_kind = secondary_direction::reflect;
    pixel_sample sample;

    const ray_kind_settings& settings(ray_kind k) const {
        return k == ray_kind::primary ? primary : k == ray_kind::shadow ? shadow : secondary;
    }
};

// Parse a scene file. Throws input_error naming the file, the line and the
// field path at fault, e.g. "spheres[2].radius": every field is checked
// (types, ranges, unknown keys), nothing is defaulted silently except what
// the format documents as optional.
scene read_scene(const std::filesystem::path& file);

// Same, from text (`file` only names it in messages).
scene parse_scene(const std::string& text, const std::filesystem::path& file);

// One ray the renderer casts. Every coordinate is exactly representable in
// the scene's precision (the generator rounds to it), so a float variant
// receives exactly these values and the oracle judges exactly them.
// The ray takes roots t with tmin < t < tmax (tmax = +inf: unbounded).
struct scene_ray {
    int x = 0, y = 0;  // the pixel that cast it
    ray_kind kind = ray_kind::primary;
    ray_query query = ray_query::nearest_hit;
    vec3<double> origin;
    vec3<double> direction;
    double tmin = 0;
    double tmax = std::numeric_limits<double>::infinity();
    int light = -1;         // shadow rays: index into scene::lights
    int from_sphere = -1;   // shadow and secondary rays: the sphere whose hit spawned it
    std::vector<int> spheres;  // indices of the spheres it can meet (all of them: no culling)

    std::string id() const;  // e.g. "px12,7/shadow0", unique within a scene
};

// Calls `pixel(x, y)` for each pixel the scene casts, in raster order. Every
// pixel: constant memory; a sample of n pixels: memory in proportion to n.
void for_each_sampled_pixel(const scene& s, const std::function<void(int, int)>& pixel);

// The same pixels, collected.
std::vector<std::pair<int, int>> sampled_pixels(const scene& s);

// The camera ray of one pixel (rounded to the scene's precision).
scene_ray primary_ray(const scene& s, int x, int y);

// The rays one pixel casts: its primary ray, then (when the exact nearest hit
// exists) its shadow rays, light by light, then its secondary ray.
std::vector<scene_ray> pixel_rays(const scene& s, int x, int y);

// Exactly the rays the renderer casts, pixel by pixel in raster order, each
// pixel's as pixel_rays gives them; memory is one pixel's rays (and the
// sample, when the scene samples pixels), whatever the resolution.
void for_each_ray(const scene& s, const std::function<void(const scene_ray&)>& ray);

// The same rays, collected (in memory in proportion to their number: for
// small scenes and tests; the audit and render stream them).
std::vector<scene_ray> generate_rays(const scene& s);

// One sphere on a ray: the (ray, sphere) pair as a case and the oracle's
// answer for it in the scene's precision.
struct sphere_solution {
    int sphere = -1;
    corpus_case pair;
    exact_solution exact;
};

// Every sphere on the ray, solved on `route`.
std::vector<sphere_solution> solve_spheres(const scene& s, const scene_ray& r,
                                           oracle_route route = oracle_route::filtered);

// The ray's exact nearest hit: over the spheres, the nearest root in the
// ray's (tmin, tmax) (the renderer's contract, compare/judge.h), roots of
// different spheres compared exactly (compare_roots); an exact tie goes to
// the sphere listed first. `index` is into `solved`.
struct exact_nearest {
    std::size_t index = 0;
    root_index root = root_index::near_root;
};
std::optional<exact_nearest> exact_nearest_hit(const scene_ray& r, std::span<const sphere_solution> solved);

// The (ray, sphere) pair as a corpus case: geometry exactly as the ray and the
// sphere are given (the sphere rounded to the scene's precision), the ray's
// tmin and tmax (tmax absent when infinite), id "<ray id>/<sphere name>".
corpus_case case_for(const scene& s, const scene_ray& r, int sphere);

}  // namespace rayverify
