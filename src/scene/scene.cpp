#include "scene/scene.h"

#include "compare/judge.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <system_error>
#include <unordered_map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "corpus/json_input.h"
#include "intersectors/pbrt_v4_sphere.h"
#include "oracle/oracle.h"

namespace rayverify {
namespace {

using scene_json = nlohmann::json;

// A scene is a page of JSON; anything near this size is not one, and the
// parsed tree takes several times the text's memory.
constexpr std::uintmax_t max_scene_file_bytes = std::uintmax_t{16} << 20;

// Reads typed fields, throwing input_error(file, line, path, problem).
class reader {
public:
    reader(std::string file, const located_json& lines) : file_(std::move(file)), lines_(lines) {}

    [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
        throw input_error(file_, lines_.line_of(path), printable(path, non_ascii_bytes::keep),
                          printable(problem, non_ascii_bytes::keep));
    }

    static std::string child(const std::string& path, const std::string& key) {
        return path.empty() ? key : path + "." + key;
    }

    // The object at `path`, with no key outside `allowed`.
    const scene_json& object(const scene_json& j, const std::string& path, std::initializer_list<const char*> allowed) const {
        if (!j.is_object()) fail(path, path.empty() ? "a scene is a JSON object {...}" : "must be an object");
        for (const auto& item : j.items()) {
            const std::string& key = item.key();  // not a structured binding: clang 14 cannot capture one
            const bool known = std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; });
            if (!known) {
                std::string list;
                for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
                fail(child(path, key), "unknown field (expected one of: " + list + ")");
            }
        }
        return j;
    }

    // A finite number: a JSON number, or a string holding a decimal or C99 hex
    // float read exactly (for values a decimal literal cannot give exactly).
    double number(const scene_json& j, const std::string& path) const {
        double v = 0;
        if (j.is_number()) {
            v = j.get<double>();
        } else if (j.is_string()) {
            v = parse_exact_double(j.get<std::string>(), file_, lines_.line_of(path), path);
        } else {
            fail(path, "must be a finite number");
        }
        if (!std::isfinite(v)) fail(path, "must be a finite number");
        return v;
    }

    double number_at_least(const scene_json& j, const std::string& path, double low, const char* what) const {
        const double v = number(j, path);
        if (!(v >= low)) fail(path, fmt::format("must be a finite number {} (got {})", what, v));
        return v;
    }

    vec3<double> vector(const scene_json& j, const std::string& path) const {
        if (!j.is_array() || j.size() != 3) fail(path, "must be an array of 3 finite numbers [x, y, z]");
        return {number(j[0], path + "[0]"), number(j[1], path + "[1]"), number(j[2], path + "[2]")};
    }

    std::string string(const scene_json& j, const std::string& path) const {
        if (!j.is_string()) fail(path, "must be a string");
        return j.get<std::string>();
    }

    bool boolean(const scene_json& j, const std::string& path) const {
        if (!j.is_boolean()) fail(path, "must be true or false");
        return j.get<bool>();
    }

    long long integer(const scene_json& j, const std::string& path, long long low, long long high) const {
        if (!j.is_number_integer() || j.get<long long>() < low || j.get<long long>() > high)
            fail(path, fmt::format("must be an integer from {} to {}", low, high));
        return j.get<long long>();
    }

    // One of a table's values, by the name its one spelling gives it.
    template <class E, std::size_t N, class NameOf>
    E choice(const scene_json& j, const std::string& path, const std::array<E, N>& values, NameOf name_of) const {
        std::vector<std::pair<const char*, E>> options;
        for (const E v : values) options.emplace_back(name_of(v), v);
        return choice(j, path, options);
    }

    template <class E>
    E choice(const scene_json& j, const std::string& path, std::initializer_list<std::pair<const char*, E>> options) const {
        return choice(j, path, std::vector<std::pair<const char*, E>>(options));
    }

    template <class E>
    E choice(const scene_json& j, const std::string& path, const std::vector<std::pair<const char*, E>>& options) const {
        std::string list;
        for (const auto& [name, value] : options) list += std::string(list.empty() ? "" : ", ") + "\"" + name + "\"";
        if (!j.is_string()) fail(path, "must be one of " + list);
        for (const auto& [name, value] : options)
            if (j.get<std::string>() == name) return value;
        fail(path, "must be one of " + list + " (got \"" + j.get<std::string>() + "\")");
    }

    const scene_json* optional(const scene_json& j, const char* key) const {
        auto it = j.find(key);
        return it == j.end() ? nullptr : &*it;
    }

    const scene_json& required(const scene_json& j, const std::string& path, const char* key) const {
        auto it = j.find(key);
        if (it == j.end()) fail(child(path, key), "is required");
        return *it;
    }

private:
    std::string file_;
    const located_json& lines_;
};

ray_query read_query(const reader& in, const scene_json& j, const std::string& path) {
    return in.choice(j, path, every_ray_query, ray_query_name);
}

spawn_settings read_spawn(const reader& in, const scene_json& j, const std::string& path) {
    spawn_settings s;
    if (const scene_json* o = in.optional(j, "offset")) {
        const std::string p = path + ".offset";
        in.object(*o, p, {"rule", "absolute", "relative"});
        s.rule = in.choice<offset_rule>(in.required(*o, p, "rule"), p + ".rule",
                                        {{"none", offset_rule::none},
                                         {"along_normal", offset_rule::along_normal},
                                         {"along_ray", offset_rule::along_ray},
                                         {"pbrt_v4", offset_rule::pbrt_v4},
                                         {"mitsuba3", offset_rule::mitsuba3}});
        const bool engine_rule = s.rule == offset_rule::pbrt_v4 || s.rule == offset_rule::mitsuba3;
        for (const char* field : {"absolute", "relative"})
            if (engine_rule && in.optional(*o, field))
                in.fail(p + "." + field, "an engine's rule (pbrt_v4, mitsuba3) takes no absolute or relative offset");
        if (const scene_json* v = in.optional(*o, "absolute"))
            s.absolute = in.number_at_least(*v, p + ".absolute", 0, "≥ 0");
        if (const scene_json* v = in.optional(*o, "relative"))
            s.relative = in.number_at_least(*v, p + ".relative", 0, "≥ 0");
    }
    if (const scene_json* v = in.optional(j, "tmin")) s.tmin = in.number_at_least(*v, path + ".tmin", 0, "≥ 0");
    return s;
}

vec3<double> cross(vec3<double> a, vec3<double> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

bool is_zero(vec3<double> v) { return v.x == 0 && v.y == 0 && v.z == 0; }

bool is_finite(vec3<double> v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// v times the power of two that puts its largest component in [1, 2): exact,
// and |v|² of the result neither overflows nor underflows. v finite, non-zero.
vec3<double> scaled_to_unit(vec3<double> v) {
    const int e = std::ilogb(std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}));
    return {std::scalbn(v.x, -e), std::scalbn(v.y, -e), std::scalbn(v.z, -e)};
}

// |v| and v/|v| take the plain formulas whenever |v|² is a normal double, so
// every ordinary scene casts the same bits as ever; only where |v|² would
// overflow (coordinates beyond 1e154) or underflow (below 1e-154) is v
// scaled first, instead of giving inf, 0 or NaN. The zero vector has no
// direction: normalised gives it back (a hit on a sphere of radius 0 has no
// normal, so a spawned ray is neither offset along it nor reflected).
double norm(vec3<double> v) {
    const double n2 = length_squared(v);
    if (std::isnormal(n2) || is_zero(v)) return std::sqrt(n2);
    const int e = std::ilogb(std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}));
    return std::scalbn(std::sqrt(length_squared(scaled_to_unit(v))), e);
}

vec3<double> normalised(vec3<double> v) {
    if (is_zero(v)) return v;
    if (!std::isnormal(length_squared(v))) v = scaled_to_unit(v);
    const double n = std::sqrt(length_squared(v));
    return {v.x / n, v.y / n, v.z / n};
}

// A vector rounded to the scene's precision (exact in double either way).
vec3<double> in_precision(vec3<double> v, precision p) {
    return {rounded_to(p, v.x), rounded_to(p, v.y), rounded_to(p, v.z)};
}

double in_precision(double v, precision p) {
    return rounded_to(p, v);
}

// d/|d| computed in precision T, as a renderer working in T normalises.
template <class T>
vec3<double> normalised_in(vec3<double> v) {
    const vec3<T> w = vec3_cast<T>(v);
    const T n = std::sqrt(length_squared(w));
    return vec3_cast<double>(vec3<T>{w.x / n, w.y / n, w.z / n});
}

// A new ray's direction as the renderer casts it: normalised in the scene's
// precision when the scene says so, else rounded to it.
vec3<double> cast_direction(const scene& s, vec3<double> d) {
    if (!s.normalise_directions) return in_precision(d, s.prec);
    return with_precision(s.prec, [&]<class T>(std::type_identity<T>) { return normalised_in<T>(d); });
}

// The camera's frame: w points backwards, u right, v up; the image plane's
// half extents. u is zero when up is parallel to the view direction.
struct camera_frame {
    vec3<double> u, v, w;
    double half_width = 0, half_height = 0;
};

camera_frame frame_of(const scene_camera& cam) {
    camera_frame f;
    f.w = normalised(cam.position - cam.look_at);
    vec3<double> side = cross(cam.up, f.w);
    // Only up's direction matters: scaled (exactly) where up × w would overflow or underflow.
    if ((!is_finite(side) || !std::isnormal(length_squared(side))) && !is_zero(cam.up))
        side = cross(scaled_to_unit(cam.up), f.w);
    f.u = normalised(side);
    f.v = cross(f.w, f.u);
    f.half_height = cam.kind == projection::perspective ? std::tan(cam.fov_degrees * std::numbers::pi / 360.0)
                                                        : cam.view_height / 2;
    f.half_width = f.half_height * cam.width / cam.height;
    return f;
}

// How far from the origin a scene may reach: an eighth of its precision's
// range, so that what the generator adds up (a hit point and its offset, a
// light minus a spawned origin) stays finite.
double scene_limit(precision p) {
    return with_precision(p, []<class T>(std::type_identity<T>) {
               return static_cast<double>(std::numeric_limits<T>::max());
           }) /
           8;
}

double reach_of(vec3<double> v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

// The hit point of the exact nearest hit, correctly rounded to the scene's
// precision, and the outward unit normal there (computed in double).
struct spawn_point {
    vec3<double> point;
    vec3<double> normal;
};

spawn_point spawn_at(const scene& s, const sphere_solution& hit, root_index root) {
    spawn_point p;
    p.point = {hit.exact.rounded_hit_coordinate(root, 0), hit.exact.rounded_hit_coordinate(root, 1),
               hit.exact.rounded_hit_coordinate(root, 2)};
    const scene_sphere& sphere = s.spheres[static_cast<std::size_t>(hit.sphere)];
    p.normal = normalised(p.point - sphere.centre);
    return p;
}

// The origin of a ray leaving P in direction d under the scene's rule, rounded
// to the scene's precision. Along the normal, the origin moves to the side the
// ray leaves to (outside for a reflection, inside for a transmission).
// pbrt-v4's OffsetRayOrigin at the sphere hit P in T.
template <class T>
vec3<double> pbrt_offset_origin(const spawn_point& p, vec3<double> centre, vec3<double> d) {
    using interval = intersectors::pbrt::interval<T>;
    const T g3 = intersectors::pbrt::gamma<T>(3), g5 = intersectors::pbrt::gamma<T>(5);
    const vec3<T> point = vec3_cast<T>(p.point), c = vec3_cast<T>(centre), n = vec3_cast<T>(p.normal);
    const vec3<T> w = vec3_cast<T>(d);
    const auto error = [&](T pk, T ck) {
        const T object = pk - ck;
        const T bound = (g3 + 1) * (g5 * std::abs(object)) + g3 * (std::abs(object) + std::abs(ck));
        const interval i = interval::from_value_and_error(pk, bound);
        return (i.high - i.low) / 2;  // Point3fi::Error()
    };
    const vec3<T> e{error(point.x, c.x), error(point.y, c.y), error(point.z, c.z)};
    const T along = std::abs(n.x) * e.x + std::abs(n.y) * e.y + std::abs(n.z) * e.z;
    vec3<T> offset = along * n;
    if (dot(w, n) < 0) offset = T(-1) * offset;
    const vec3<T> moved = point + offset;
    const auto away = [](T po, T off) {
        return off > 0 ? intersectors::pbrt::next_float_up(po) : off < 0 ? intersectors::pbrt::next_float_down(po) : po;
    };
    return vec3_cast<double>(vec3<T>{away(moved.x, offset.x), away(moved.y, offset.y), away(moved.z, offset.z)});
}

// Mitsuba 3's Interaction::offset_p at P in T.
template <class T>
vec3<double> mitsuba_offset_origin(const spawn_point& p, vec3<double> d) {
    const T ray_epsilon = static_cast<T>(0x1p-24f * 1500);  // dr::Epsilon<float32> · 1500 (MI_ENABLE_EMBREE)
    const vec3<T> point = vec3_cast<T>(p.point), n = vec3_cast<T>(p.normal), w = vec3_cast<T>(d);
    const T largest = std::max({std::abs(point.x), std::abs(point.y), std::abs(point.z)});
    const T magnitude = std::copysign((T(1) + largest) * ray_epsilon, dot(n, w));
    return vec3_cast<double>(vec3<T>{std::fma(magnitude, n.x, point.x), std::fma(magnitude, n.y, point.y),
                                     std::fma(magnitude, n.z, point.z)});
}

vec3<double> spawn_origin(const scene& s, const spawn_settings& rule, const spawn_point& p, vec3<double> d,
                          vec3<double> centre) {
    const bool in_float = s.prec == precision::binary32;
    if (rule.rule == offset_rule::pbrt_v4)
        return in_float ? pbrt_offset_origin<float>(p, centre, d) : pbrt_offset_origin<double>(p, centre, d);
    if (rule.rule == offset_rule::mitsuba3)
        return in_float ? mitsuba_offset_origin<float>(p, d) : mitsuba_offset_origin<double>(p, d);
    const double offset = rule.absolute + rule.relative * norm(p.point);
    vec3<double> o = p.point;
    if (rule.rule == offset_rule::along_normal) {
        const double side = dot(d, p.normal) < 0 ? -1.0 : 1.0;
        o = o + (side * offset) * p.normal;
    } else if (rule.rule == offset_rule::along_ray) {
        o = o + offset * normalised(d);
    }
    return in_precision(o, s.prec);
}

std::vector<int> all_spheres(const scene& s) {
    std::vector<int> v(s.spheres.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<int>(i);
    return v;
}

}  // namespace

const char* ray_kind_name(ray_kind k) {
    switch (k) {
        case ray_kind::primary: return "primary";
        case ray_kind::shadow: return "shadow";
        case ray_kind::secondary: return "secondary";
    }
    return "?";
}

std::string scene_ray::id() const {
    std::string s = fmt::format("px{},{}/{}", x, y, ray_kind_name(kind));
    if (kind == ray_kind::shadow) s += std::to_string(light);
    return s;
}

namespace {

// How far a scene may reach in its precision: every point the generator
// computes (origins, hit points, lights) must be finite there, refused at the
// field that reaches too far.
struct scene_bounds {
    const reader& in;
    precision prec;
    double limit;

    void within_limit(double reach, const std::string& path, const std::string& what) const {
        if (!(reach <= limit))
            in.fail(path, fmt::format("{} reaches {:g} from the origin; a {} scene must lie within ±{:g} (an eighth "
                                      "of its range), so that every ray it casts stays finite",
                                      what, reach, precision_name(prec), limit));
    }
    void finite_in_precision(double value, const std::string& path) const {
        if (!std::isfinite(in_precision(value, prec))) in.fail(path, "overflows the scene's precision");
    }
};

// "spheres": each named once, finite in the precision, within reach.
void read_spheres(const reader& in, const scene_json& root, const scene_bounds& bounds, scene& s) {
    const scene_json& spheres = in.required(root, "", "spheres");
    if (!spheres.is_array() || spheres.empty()) in.fail("spheres", "must be a non-empty array of spheres");
    std::set<std::string> names;
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const std::string p = fmt::format("spheres[{}]", i);
        in.object(spheres[i], p, {"name", "centre", "radius", "comment"});
        scene_sphere sphere;
        sphere.name = fmt::format("sphere{}", i);
        if (const scene_json* v = in.optional(spheres[i], "name")) sphere.name = in.string(*v, p + ".name");
        if (sphere.name.empty() || sphere.name.find_first_of(" \t/") != std::string::npos)
            in.fail(p + ".name", "must be a non-empty name without spaces or '/'");
        if (!names.insert(sphere.name).second) in.fail(p + ".name", "names another sphere too: \"" + sphere.name + "\"");
        sphere.centre = in.vector(in.required(spheres[i], p, "centre"), p + ".centre");
        sphere.radius = in.number_at_least(in.required(spheres[i], p, "radius"), p + ".radius", 0, "≥ 0");
        const vec3<double> c = in_precision(sphere.centre, bounds.prec);
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
            in.fail(p + ".centre", "overflows the scene's precision");
        if (!std::isfinite(in_precision(sphere.radius, bounds.prec))) in.fail(p + ".radius", "overflows the scene's precision");
        bounds.within_limit(reach_of(sphere.centre) + sphere.radius, p, "the sphere (|centre| + radius)");
        s.spheres.push_back(sphere);
    }
}

// "camera": its projection and frame, and every pixel's ray finite.
void read_camera(const reader& in, const scene_json& root, const scene_bounds& bounds, scene& s) {
    const scene_json& camera = in.required(root, "", "camera");
    in.object(camera, "camera", {"projection", "position", "look_at", "up", "fov_degrees", "view_height", "resolution"});
    scene_camera& cam = s.camera;
    cam.kind = in.choice<projection>(in.required(camera, "camera", "projection"), "camera.projection",
                                     {{"perspective", projection::perspective},
                                      {"orthographic", projection::orthographic}});
    cam.position = in.vector(in.required(camera, "camera", "position"), "camera.position");
    cam.look_at = in.vector(in.required(camera, "camera", "look_at"), "camera.look_at");
    if (const scene_json* v = in.optional(camera, "up")) cam.up = in.vector(*v, "camera.up");
    if (cam.look_at == cam.position) in.fail("camera.look_at", "must differ from camera.position");
    if (cam.kind == projection::perspective) {
        if (camera.contains("view_height")) in.fail("camera.view_height", "applies to an orthographic camera only");
        const double fov = in.number(in.required(camera, "camera", "fov_degrees"), "camera.fov_degrees");
        if (!(fov > 0 && fov < 180)) in.fail("camera.fov_degrees", fmt::format("must lie in (0, 180) degrees (got {})", fov));
        cam.fov_degrees = fov;
    } else {
        if (camera.contains("fov_degrees")) in.fail("camera.fov_degrees", "applies to a perspective camera only");
        const double h = in.number(in.required(camera, "camera", "view_height"), "camera.view_height");
        if (!(h > 0)) in.fail("camera.view_height", fmt::format("must be a finite number > 0 (got {})", h));
        cam.view_height = h;
    }
    const scene_json& resolution = in.required(camera, "camera", "resolution");
    if (!resolution.is_array() || resolution.size() != 2)
        in.fail("camera.resolution", "must be [width, height] in pixels");
    cam.width = static_cast<int>(in.integer(resolution[0], "camera.resolution[0]", 1, 4096));
    cam.height = static_cast<int>(in.integer(resolution[1], "camera.resolution[1]", 1, 4096));
    bounds.within_limit(reach_of(cam.position), "camera.position", "the camera");
    bounds.within_limit(reach_of(cam.look_at), "camera.look_at", "the point looked at");
    if (is_zero(frame_of(cam).u)) in.fail("camera.up", "must not be parallel to the view direction");
    // Every other pixel's ray lies between the corners'.
    for (const int x : {0, cam.width - 1})
        for (const int y : {0, cam.height - 1}) {
            const scene_ray corner = primary_ray(s, x, y);
            const char* field = cam.kind == projection::orthographic ? "camera.view_height" : "camera";
            bounds.within_limit(reach_of(corner.origin), field, fmt::format("the ray of pixel ({}, {}) starts at a point that", x, y));
            if (!is_finite(corner.direction))
                in.fail("camera", fmt::format("the ray of pixel ({}, {}) has a non-finite direction", x, y));
        }
}

// "lights": each named once, within reach.
void read_lights(const reader& in, const scene_json& root, const scene_bounds& bounds, scene& s) {
    if (const scene_json* lights = in.optional(root, "lights")) {
        if (!lights->is_array()) in.fail("lights", "must be an array of lights");
        std::set<std::string> light_names;
        for (std::size_t i = 0; i < lights->size(); ++i) {
            const std::string p = fmt::format("lights[{}]", i);
            in.object((*lights)[i], p, {"name", "position"});
            scene_light light;
            light.name = fmt::format("light{}", i);
            if (const scene_json* v = in.optional((*lights)[i], "name")) light.name = in.string(*v, p + ".name");
            if (light.name.empty() || light.name.find_first_of(" \t/") != std::string::npos)
                in.fail(p + ".name", "must be a non-empty name without spaces or '/'");
            if (!light_names.insert(light.name).second)
                in.fail(p + ".name", "names another light too: \"" + light.name + "\"");
            light.position = in.vector(in.required((*lights)[i], p, "position"), p + ".position");
            bounds.within_limit(reach_of(light.position), p + ".position", "the light");
            s.lights.push_back(light);
        }
    }
}

// "rays": the kinds cast, each with its query and spawn settings.
void read_rays(const reader& in, const scene_json& root, scene& s) {
    if (const scene_json* rays = in.optional(root, "rays")) {
        in.object(*rays, "rays", {"primary", "shadow", "secondary"});
        if (const scene_json* p = in.optional(*rays, "primary")) {
            in.object(*p, "rays.primary", {"query", "tmin"});
            if (const scene_json* v = in.optional(*p, "query")) s.primary.query = read_query(in, *v, "rays.primary.query");
            if (s.primary.query == ray_query::any_hit)
                in.fail("rays.primary.query", "any_hit is for shadow rays: a camera ray needs the hit it sees");
            if (const scene_json* v = in.optional(*p, "tmin"))
                s.primary_tmin = in.number_at_least(*v, "rays.primary.tmin", 0, "≥ 0");
        }
        if (const scene_json* p = in.optional(*rays, "shadow")) {
            in.object(*p, "rays.shadow", {"query", "offset", "tmin"});
            s.shadow.enabled = true;
            if (const scene_json* v = in.optional(*p, "query")) s.shadow.query = read_query(in, *v, "rays.shadow.query");
            s.shadow_spawn = read_spawn(in, *p, "rays.shadow");
            if (s.lights.empty()) in.fail("rays.shadow", "shadow rays need at least one entry in \"lights\"");
        }
        if (const scene_json* p = in.optional(*rays, "secondary")) {
            in.object(*p, "rays.secondary", {"query", "offset", "tmin", "direction"});
            s.secondary.enabled = true;
            if (const scene_json* v = in.optional(*p, "query")) s.secondary.query = read_query(in, *v, "rays.secondary.query");
            if (const scene_json* v = in.optional(*p, "direction"))
                s.secondary_kind = in.choice<secondary_direction>(
                    *v, "rays.secondary.direction",
                    {{"reflect", secondary_direction::reflect}, {"transmit", secondary_direction::transmit}});
            s.secondary_spawn = read_spawn(in, *p, "rays.secondary");
        }
    }
}

// Spawned origins: a hit point (within its sphere's reach) moved by the offset.
void check_spawned_origins(const scene_bounds& bounds, const scene& s) {
    double sphere_reach = 0;
    for (const scene_sphere& sphere : s.spheres)
        sphere_reach = std::max(sphere_reach, reach_of(sphere.centre) + sphere.radius);
    bounds.finite_in_precision(s.primary_tmin, "rays.primary.tmin");
    const auto check_spawn = [&](const ray_kind_settings& kind, const spawn_settings& spawn, const std::string& path) {
        if (!kind.enabled) return;
        bounds.within_limit(sphere_reach + spawn.absolute + spawn.relative * 2 * sphere_reach, path + ".offset",
                     "an origin spawned on a sphere and offset");
        bounds.finite_in_precision(spawn.tmin, path + ".tmin");
    };
    check_spawn(s.shadow, s.shadow_spawn, "rays.shadow");
    check_spawn(s.secondary, s.secondary_spawn, "rays.secondary");
}

// "pixels": "all", or a sample of {"count": N, "seed": S}.
void read_pixels(const reader& in, const scene_json& root, scene& s) {
    if (const scene_json* pixels = in.optional(root, "pixels")) {
        if (pixels->is_string()) {
            if (pixels->get<std::string>() != "all") in.fail("pixels", "must be \"all\" or {\"count\": N, \"seed\": S}");
        } else {
            in.object(*pixels, "pixels", {"count", "seed"});
            s.sample.all = false;
            const long long total = static_cast<long long>(s.camera.width) * s.camera.height;
            s.sample.count = static_cast<std::size_t>(
                in.integer(in.required(*pixels, "pixels", "count"), "pixels.count", 1, total));
            s.sample.seed = static_cast<std::uint64_t>(
                in.integer(in.required(*pixels, "pixels", "seed"), "pixels.seed", 0, std::numeric_limits<long long>::max()));
        }
    }
}

}  // namespace

scene parse_scene(const std::string& text, const std::filesystem::path& file) {
    const std::string name = file.string();
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
        throw input_error(name, 0, "", "empty file: a scene is a JSON object (corpus/scenes/README.md)");
    // Parsed by the one reader of JSON input: a syntax error, a duplicate key,
    // a number beyond double range or a nesting too deep is refused with its
    // line and field, and every value's line is kept for the checks below.
    const located_json parsed = parse_located_json_input(text, name);
    const scene_json root = parsed.document;
    const reader in(name, parsed);

    scene s;
    s.file = file;
    s.name = file.stem().string();
    in.object(root, "", {"comment", "precision", "normalise_directions", "spheres", "camera", "lights", "rays",
                         "pixels"});
    if (const scene_json* v = in.optional(root, "comment")) s.comment = in.string(*v, "comment");
    s.prec = in.choice(in.required(root, "", "precision"), "precision", every_precision, precision_name);
    if (const scene_json* v = in.optional(root, "normalise_directions"))
        s.normalise_directions = in.boolean(*v, "normalise_directions");
    const scene_bounds bounds{in, s.prec, scene_limit(s.prec)};
    read_spheres(in, root, bounds, s);
    read_camera(in, root, bounds, s);
    read_lights(in, root, bounds, s);
    read_rays(in, root, s);
    check_spawned_origins(bounds, s);
    read_pixels(in, root, s);
    return s;
}

scene read_scene(const std::filesystem::path& file) {
    namespace fs = std::filesystem;
    const std::string name = file.string();
    // Checked before opening: an ifstream opens a directory and reads it as
    // empty, which would be reported as broken JSON.
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (status.type() == fs::file_type::not_found) throw input_error(name, 0, "", "no such file");
    if (ec) throw input_error(name, 0, "", ec.message());
    if (fs::is_directory(status)) throw input_error(name, 0, "", "is a directory, expected a scene file");
    if (!fs::is_regular_file(status)) throw input_error(name, 0, "", "is not a regular file");
    const auto too_large = [&](std::uintmax_t size) {
        return input_error(name, 0, "",
                           fmt::format("is {} bytes, over the {} MiB limit for a scene file", size,
                                       max_scene_file_bytes >> 20));
    };
    const std::uintmax_t size = fs::file_size(file, ec);
    if (!ec && size > max_scene_file_bytes) throw too_large(size);

    std::ifstream in(file, std::ios::binary);
    if (!in) throw input_error(name, 0, "", fmt::format("cannot open: {}", std::generic_category().message(errno)));
    std::string text;
    std::array<char, 1 << 16> chunk{};
    // Capped while reading too: a file may grow meanwhile.
    while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
        const auto n = static_cast<std::size_t>(in.gcount());
        if (text.size() + n > max_scene_file_bytes) throw too_large(text.size() + n);
        text.append(chunk.data(), n);
    }
    if (in.bad()) throw input_error(name, 0, "", "cannot read");
    return parse_scene(text, file);
}

void for_each_sampled_pixel(const scene& s, const std::function<void(int, int)>& pixel) {
    const std::size_t width = static_cast<std::size_t>(s.camera.width);
    const std::size_t total = width * static_cast<std::size_t>(s.camera.height);
    const auto visit = [&](std::size_t i) { pixel(static_cast<int>(i % width), static_cast<int>(i / width)); };
    if (s.sample.all) {
        for (std::size_t i = 0; i < total; ++i) visit(i);
        return;
    }
    // A partial Fisher–Yates shuffle of 0 … total − 1 whose first `count`
    // entries are a uniform sample; only the entries it moved are stored.
    const std::size_t count = std::min(s.sample.count, total);
    std::mt19937_64 random(s.sample.seed);
    std::unordered_map<std::size_t, std::size_t> moved;
    const auto entry = [&](std::size_t i) {
        const auto at = moved.find(i);
        return at == moved.end() ? i : at->second;
    };
    std::vector<std::size_t> chosen(count);
    for (std::size_t i = 0; i < count; ++i) {
        std::uniform_int_distribution<std::size_t> pick(i, total - 1);
        const std::size_t j = pick(random);
        const std::size_t at_i = entry(i), at_j = entry(j);
        moved[j] = at_i;
        chosen[i] = at_j;
        moved.erase(i);  // entry i is never read again
    }
    std::sort(chosen.begin(), chosen.end());
    for (std::size_t i : chosen) visit(i);
}

std::vector<std::pair<int, int>> sampled_pixels(const scene& s) {
    std::vector<std::pair<int, int>> pixels;
    for_each_sampled_pixel(s, [&](int x, int y) { pixels.emplace_back(x, y); });
    return pixels;
}

scene_ray primary_ray(const scene& s, int x, int y) {
    const scene_camera& cam = s.camera;
    const auto [u, v, w, half_width, half_height] = frame_of(cam);
    // Pixel centre on the image plane, in [−1, 1] times the half extents.
    const double sx = ((x + 0.5) / cam.width * 2 - 1) * half_width;
    const double sy = (1 - (y + 0.5) / cam.height * 2) * half_height;

    scene_ray r;
    r.x = x;
    r.y = y;
    r.kind = ray_kind::primary;
    r.query = s.primary.query;
    r.tmin = in_precision(s.primary_tmin, s.prec);
    r.spheres = all_spheres(s);
    if (cam.kind == projection::perspective) {
        r.origin = in_precision(cam.position, s.prec);
        r.direction = cast_direction(s, sx * u + sy * v - w);
    } else {
        r.origin = in_precision(cam.position + sx * u + sy * v, s.prec);
        r.direction = cast_direction(s, -1.0 * w);
    }
    return r;
}

std::vector<scene_ray> pixel_rays(const scene& s, int x, int y) {
    std::vector<scene_ray> rays;
    const scene_ray primary = primary_ray(s, x, y);
    rays.push_back(primary);
    if (!s.shadow.enabled && !s.secondary.enabled) return rays;
    const std::vector<sphere_solution> solved = solve_spheres(s, primary);
    const std::optional<exact_nearest> nearest = exact_nearest_hit(primary, solved);
    if (!nearest) return rays;
    const sphere_solution* hit = &solved[nearest->index];
    const spawn_point p = spawn_at(s, *hit, nearest->root);
    const vec3<double> sphere_centre = in_precision(s.spheres[static_cast<std::size_t>(hit->sphere)].centre, s.prec);

    if (s.shadow.enabled) {
        for (std::size_t l = 0; l < s.lights.size(); ++l) {
            scene_ray r;
            r.x = x;
            r.y = y;
            r.kind = ray_kind::shadow;
            r.query = s.shadow.query;
            r.light = static_cast<int>(l);
            r.from_sphere = hit->sphere;
            r.spheres = all_spheres(s);
            const vec3<double> light = in_precision(s.lights[l].position, s.prec);
            r.origin = spawn_origin(s, s.shadow_spawn, p, light - p.point, sphere_centre);
            const vec3<double> to_light = light - r.origin;
            r.direction = cast_direction(s, to_light);
            // Unnormalised: the light is at t = 1; normalised: at its distance.
            r.tmax = s.normalise_directions ? in_precision(norm(to_light), s.prec) : 1.0;
            r.tmin = in_precision(s.shadow_spawn.tmin, s.prec);
            if (!(r.tmin < r.tmax)) continue;  // the light sits on the spawn point
            rays.push_back(std::move(r));
        }
    }
    if (s.secondary.enabled) {
        scene_ray r;
        r.x = x;
        r.y = y;
        r.kind = ray_kind::secondary;
        r.query = s.secondary.query;
        r.from_sphere = hit->sphere;
        r.spheres = all_spheres(s);
        const vec3<double> d = primary.direction;
        const vec3<double> new_d = s.secondary_kind == secondary_direction::reflect
                                       ? d - (2 * dot(d, p.normal)) * p.normal
                                       : d;
        r.origin = spawn_origin(s, s.secondary_spawn, p, new_d, sphere_centre);
        r.direction = cast_direction(s, new_d);
        r.tmin = in_precision(s.secondary_spawn.tmin, s.prec);
        rays.push_back(std::move(r));
    }
    return rays;
}

void for_each_ray(const scene& s, const std::function<void(const scene_ray&)>& ray) {
    for_each_sampled_pixel(s, [&](int x, int y) {
        for (const scene_ray& r : pixel_rays(s, x, y)) ray(r);
    });
}

std::vector<scene_ray> generate_rays(const scene& s) {
    std::vector<scene_ray> rays;
    for_each_ray(s, [&](const scene_ray& r) { rays.push_back(r); });
    return rays;
}

std::vector<sphere_solution> solve_spheres(const scene& s, const scene_ray& r, oracle_route route) {
    std::vector<sphere_solution> solved;
    solved.reserve(r.spheres.size());
    for (int k : r.spheres) {
        sphere_solution one{k, case_for(s, r, k), {}};
        one.exact = solve_case(one.pair, s.prec, route);
        solved.push_back(std::move(one));
    }
    return solved;
}

std::optional<exact_nearest> exact_nearest_hit(const scene_ray& r, std::span<const sphere_solution> solved) {
    const contract renderer = renderer_contract(ray_query::nearest_hit);
    std::optional<exact_nearest> best;
    for (std::size_t i = 0; i < solved.size(); ++i) {
        const exact_solution& e = solved[i].exact;
        if (!e.valid()) continue;
        const expected_hit want = expect_hit(renderer, e, range_of(renderer, r.tmin, r.tmax));
        if (!want.hit()) continue;
        if (!best || compare_roots(e, want.root, solved[best->index].exact, best->root) == comparison::smaller)
            best = exact_nearest{i, want.root};
    }
    return best;
}

corpus_case case_for(const scene& s, const scene_ray& r, int sphere) {
    const scene_sphere& sp = s.spheres.at(static_cast<std::size_t>(sphere));
    corpus_case c;
    c.id = r.id() + "/" + sp.name;
    c.family = std::string("scene:") + ray_kind_name(r.kind);
    c.geometry = {r.origin, r.direction, in_precision(sp.centre, s.prec), in_precision(sp.radius, s.prec)};
    c.tmin = r.tmin;
    if (!std::isinf(r.tmax)) c.tmax = r.tmax;
    c.source = s.file.string();
    return c;
}

}  // namespace rayverify
