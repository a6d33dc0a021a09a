#include "plugin/plugin_loader.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cmath>
#include <deque>
#include <limits>
#include <memory>
#include <mutex>

#include "core/input_error.h"
#include "plugin/rayverify_plugin.h"

namespace rayverify {
namespace {

[[noreturn]] void fail(const std::filesystem::path& library, const std::string& problem) {
    throw input_error(library.string(), 0, "--plugin", problem);
}

// contract::tangent_rule is a string_view; a plugin's text is copied here so
// that it outlives any unloading of the library.
std::string_view interned(std::string text) {
    static std::mutex mutex;
    static std::deque<std::string> strings;
    const std::lock_guard lock(mutex);
    return strings.emplace_back(std::move(text));
}

std::string text_or(const char* text, std::string fallback) { return text ? std::string(text) : fallback; }

// The interval the contract is judged on, passed to the plugin as tmin/tmax.
template <class T>
T interval_start(const contract& promises) {
    return promises.query == query_kind::line_roots ? -std::numeric_limits<T>::infinity() : T(0);
}

// For the kinds that take an interval: the plugin asked for (tmin, tmax).
template <class T, class Fn>
std::function<root_pair<T>(const ray_sphere<T>&, T, T)> wrap_in(Fn intersect, std::shared_ptr<void> handle) {
    return [intersect, handle = std::move(handle)](const ray_sphere<T>& s, T tmin, T tmax) {
        const T o[3] = {s.origin.x, s.origin.y, s.origin.z};
        const T d[3] = {s.direction.x, s.direction.y, s.direction.z};
        const T c[3] = {s.centre.x, s.centre.y, s.centre.z};
        T roots[2] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::quiet_NaN()};
        const int count = intersect(o, d, c, s.radius, tmin, tmax, roots);
        return root_pair<T>{count, roots[0], roots[1]};
    };
}

template <class T, class Fn>
std::function<root_pair<T>(const ray_sphere<T>&)> wrap(Fn intersect, std::shared_ptr<void> handle,
                                                       const contract& promises) {
    const T tmin = interval_start<T>(promises);
    return [intersect, handle = std::move(handle), tmin](const ray_sphere<T>& s) {
        const T o[3] = {s.origin.x, s.origin.y, s.origin.z};
        const T d[3] = {s.direction.x, s.direction.y, s.direction.z};
        const T c[3] = {s.centre.x, s.centre.y, s.centre.z};
        // NaN until written, so a plugin that reports a hit without writing its roots is judged non_finite.
        T roots[2] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::quiet_NaN()};
        const int count = intersect(o, d, c, s.radius, tmin, std::numeric_limits<T>::infinity(), roots);
        return root_pair<T>{count, roots[0], roots[1]};
    };
}

}  // namespace

variant load_plugin(const std::filesystem::path& library) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(library, error)) fail(library, "no such file (expected a shared library)");
    // An absolute path, so that dlopen never searches LD_LIBRARY_PATH for a bare name.
    const std::filesystem::path absolute = std::filesystem::absolute(library, error);
    dlerror();
    void* raw = dlopen(absolute.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!raw) fail(library, fmt::format("cannot load: {}", text_or(dlerror(), "dlopen failed")));
    const std::shared_ptr<void> handle(raw, [](void* h) { dlclose(h); });

    const auto symbol = [&](const char* name, bool required) -> void* {
        dlerror();
        void* address = dlsym(handle.get(), name);
        if (!address && required)
            fail(library, fmt::format("missing symbol {} (see rayverify_plugin.h; in C++ declare it extern \"C\")",
                                      name));
        return address;
    };
    const auto describe = reinterpret_cast<rayverify_describe_fn>(symbol("rayverify_plugin_describe", true));
    const auto run_double =
        reinterpret_cast<rayverify_intersect_double_fn>(symbol("rayverify_plugin_intersect_double", true));
    const auto run_float =
        reinterpret_cast<rayverify_intersect_float_fn>(symbol("rayverify_plugin_intersect_float", false));

    const rayverify_plugin_info* info = describe();
    if (!info) fail(library, "rayverify_plugin_describe() returned NULL");
    if (info->abi_version != RAYVERIFY_PLUGIN_ABI_VERSION)
        fail(library, fmt::format("plugin ABI version {}, this rayverify reads version {}; rebuild the plugin "
                                  "against this rayverify_plugin.h",
                                  info->abi_version, RAYVERIFY_PLUGIN_ABI_VERSION));
    const std::string name = text_or(info->name, "");
    if (name.empty()) fail(library, "the plugin's name is empty");
    if (name.find_first_of(" \t\r\n/#") != std::string::npos)
        fail(library, fmt::format("the plugin's name '{}' must be one token without '/' or '#'", name));
    if (info->query < RAYVERIFY_LINE_ROOTS || info->query > RAYVERIFY_NEAREST_IN_INTERVAL)
        fail(library, fmt::format("unknown query kind {} (RAYVERIFY_LINE_ROOTS, RAYVERIFY_NEAREST_ON_RAY, "
                                  "RAYVERIFY_ANY_HIT_IN_INTERVAL or RAYVERIFY_NEAREST_IN_INTERVAL)",
                                  info->query));

    variant v;
    v.name = name;
    v.citation = text_or(info->citation, "plugin " + library.filename().string());
    v.formula = text_or(info->formula, "(not stated)");
    constexpr query_kind kinds[] = {query_kind::line_roots, query_kind::nearest_on_ray,
                                    query_kind::any_hit_in_interval, query_kind::nearest_in_interval};
    v.promises.query = kinds[info->query];
    v.promises.assumes_unit_direction = info->assumes_unit_direction != 0;
    v.promises.reports_tangent = info->reports_tangent != 0;
    v.promises.clamps_to_zero = info->clamps_to_zero != 0;
    v.promises.tangent_rule = interned(text_or(info->tangent_rule, v.promises.reports_tangent ? "(not stated)" : "never"));
    v.run_double = wrap<double>(run_double, handle, v.promises);
    if (run_float) v.run_float = wrap<float>(run_float, handle, v.promises);
    if (takes_interval(v.promises.query)) {
        v.run_double_in = wrap_in<double>(run_double, handle);
        if (run_float) v.run_float_in = wrap_in<float>(run_float, handle);
    }
    v.thread_safe = false;  // rayverify_plugin.h: "Called from one thread"
    return v;
}

}  // namespace rayverify
