#include "plugin/plugin_library.h"

#include <dlfcn.h>
#include <fmt/format.h>


namespace rayverify::plugin_internal {
namespace {

[[noreturn]] void fail(const std::string& problem) { throw unusable_library(problem); }

std::string text_or(const char* text, std::string fallback) { return text ? std::string(text) : fallback; }

}  // namespace

opened_library open_library(const std::filesystem::path& library) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(library, error)) fail("no such file (expected a shared library)");
    // An absolute path, so that dlopen never searches LD_LIBRARY_PATH for a bare name.
    const std::filesystem::path absolute = std::filesystem::absolute(library, error);
    dlerror();
    void* raw = dlopen(absolute.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!raw) fail(fmt::format("cannot load: {}", text_or(dlerror(), "dlopen failed")));
    opened_library opened;
    opened.handle = std::shared_ptr<void>(raw, [](void* h) { dlclose(h); });

    const auto symbol = [&](const char* name, bool required) -> void* {
        dlerror();
        void* address = dlsym(opened.handle.get(), name);
        if (!address && required)
            fail(fmt::format("missing symbol {} (see rayverify_plugin.h; in C++ declare it extern \"C\")", name));
        return address;
    };
    const auto describe = reinterpret_cast<rayverify_describe_fn>(symbol("rayverify_plugin_describe", true));
    opened.run_double =
        reinterpret_cast<rayverify_intersect_double_fn>(symbol("rayverify_plugin_intersect_double", true));
    opened.run_float = reinterpret_cast<rayverify_intersect_float_fn>(symbol("rayverify_plugin_intersect_float", false));

    const rayverify_plugin_info* info = describe();
    if (!info) fail("rayverify_plugin_describe() returned NULL");
    if (info->abi_version != RAYVERIFY_PLUGIN_ABI_VERSION)
        fail(fmt::format("plugin ABI version {}, this rayverify reads version {}; rebuild the plugin "
                         "against this rayverify_plugin.h",
                         info->abi_version, RAYVERIFY_PLUGIN_ABI_VERSION));
    plugin_description& d = opened.description;
    d.name = text_or(info->name, "");
    if (d.name.empty()) fail("the plugin's name is empty");
    if (d.name.find_first_of(" \t\r\n/#") != std::string::npos)
        fail(fmt::format("the plugin's name '{}' must be one token without '/' or '#'", d.name));
    if (info->query < RAYVERIFY_LINE_ROOTS || info->query > RAYVERIFY_NEAREST_IN_INTERVAL)
        fail(fmt::format("unknown query kind {} (RAYVERIFY_LINE_ROOTS, RAYVERIFY_NEAREST_ON_RAY, "
                         "RAYVERIFY_ANY_HIT_IN_INTERVAL or RAYVERIFY_NEAREST_IN_INTERVAL)",
                         info->query));
    d.citation = text_or(info->citation, "plugin " + library.filename().string());
    d.formula = text_or(info->formula, "(not stated)");
    d.query = info->query;
    d.assumes_unit_direction = info->assumes_unit_direction != 0;
    d.reports_tangent = info->reports_tangent != 0;
    d.clamps_to_zero = info->clamps_to_zero != 0;
    d.tangent_rule = text_or(info->tangent_rule, d.reports_tangent ? "(not stated)" : "never");
    d.has_float = opened.run_float != nullptr;
    return opened;
}

variant described_variant(const plugin_description& d) {
    variant v;
    v.name = d.name;
    v.citation = d.citation;
    v.formula = d.formula;
    contract& c = v.promises;
    switch (d.query) {
        case RAYVERIFY_LINE_ROOTS: c.query = query_kind::line_roots; break;
        case RAYVERIFY_NEAREST_ON_RAY:  // "the nearest hit with t >= 0": a ray closed at 0
            c.query = query_kind::nearest_hit;
            c.lower_end = end_kind::closed;
            c.inside = d.clamps_to_zero ? inside_rule::clamp : inside_rule::far_root;
            break;
        case RAYVERIFY_ANY_HIT_IN_INTERVAL:
            c.query = query_kind::any_hit;
            c.range = range_source::interval;
            break;
        case RAYVERIFY_NEAREST_IN_INTERVAL:
            c.query = query_kind::nearest_hit;
            c.range = range_source::interval;
            break;
    }
    c.assumes_unit_direction = d.assumes_unit_direction;
    c.reports_tangent = d.reports_tangent;
    c.tangent_rule = interned_text(d.tangent_rule);  // outlives an unloaded library
    v.thread_safe = false;  // rayverify_plugin.h: "Called from one thread"
    return v;
}

}  // namespace rayverify::plugin_internal
