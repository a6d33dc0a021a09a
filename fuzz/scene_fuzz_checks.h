// What the scene-reader fuzz target checks on one input, shared with
// tests/fuzz_regression_test.cpp (which replays every seed and saved finding).
// Returns the violated invariant, or nullopt when all hold.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>

#include "core/input_error.h"
#include "refusal_check.h"
#include "core/ray_sphere_case.h"
#include "scene/scene.h"

namespace rayverify::fuzz {

// Rays are generated only for scenes that cast at most this many pixels, so
// one input stays fast whatever resolution it asks for.
inline constexpr std::size_t scene_fuzz_max_pixels = 64;

inline bool finite_vec(const vec3<double>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The bytes are a scene file. The reader either throws an input_error that
// names this file and a line that exists (and nothing else), or returns a
// scene whose every number is usable: finite coordinates, non-negative radii,
// a positive resolution, uniquely named spheres and lights. For a small scene
// every generated ray has a finite origin, a finite direction and a finite
// tmin <= tmax, and every (ray, sphere) pair is a case the oracle can score
// in the scene's precision.
inline std::optional<std::string> check_scene_reader_input(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string file = "fuzz.json";
    scene s;
    try {
        s = parse_scene(text, file);
    } catch (const input_error& e) {
        return check_refusal(e, text, file);
    } catch (const std::exception& e) {
        return "threw something other than input_error: " + std::string(e.what());
    }
    std::unordered_set<std::string> names;
    for (const scene_sphere& sphere : s.spheres) {
        if (!finite_vec(sphere.centre)) return "sphere " + sphere.name + " accepted with a non-finite centre";
        if (!(sphere.radius >= 0) || !std::isfinite(sphere.radius))
            return "sphere " + sphere.name + " accepted with a bad radius";
        if (!names.insert(sphere.name).second) return "duplicate sphere name accepted: " + sphere.name;
    }
    if (s.camera.width <= 0 || s.camera.height <= 0) return "camera accepted with an empty resolution";
    if (!finite_vec(s.camera.position) || !finite_vec(s.camera.look_at) || !finite_vec(s.camera.up))
        return "camera accepted with a non-finite vector";
    std::unordered_set<std::string> light_names;
    for (const scene_light& light : s.lights) {
        if (!finite_vec(light.position)) return "light " + light.name + " accepted with a non-finite position";
        if (!light_names.insert(light.name).second) return "duplicate light name accepted: " + light.name;
    }

    const std::size_t pixels = s.sample.all ? static_cast<std::size_t>(s.camera.width) *
                                                  static_cast<std::size_t>(s.camera.height)
                                            : s.sample.count;
    if (pixels > scene_fuzz_max_pixels) return std::nullopt;
    std::unordered_set<std::string> ids;
    for (const scene_ray& ray : generate_rays(s)) {
        if (!ids.insert(ray.id()).second) return "two rays share the id " + ray.id();
        if (!finite_vec(ray.origin) || !finite_vec(ray.direction)) return "ray " + ray.id() + " is not finite";
        if (!std::isfinite(ray.tmin) || !(ray.tmin <= ray.tmax))
            return "ray " + ray.id() + " has an infinite tmin or tmin > tmax";
        for (int sphere : ray.spheres) {
            if (sphere < 0 || static_cast<std::size_t>(sphere) >= s.spheres.size())
                return "ray " + ray.id() + " names a sphere that does not exist";
            const corpus_case c = case_for(s, ray, sphere);
            // A degenerate camera (look_at == position) may give a zero
            // direction; the case must then say so instead of passing as valid.
            const bool zero = c.geometry.direction.x == 0 && c.geometry.direction.y == 0 &&
                              c.geometry.direction.z == 0;
            const invalid_reason why = s.prec == precision::binary32 ? validity<float>(c.geometry)
                                                                      : validity<double>(c.geometry);
            if (zero != (why == invalid_reason::zero_direction))
                return "case " + c.id + " has a zero direction its validity does not report";
        }
    }
    return std::nullopt;
}

}  // namespace rayverify::fuzz
