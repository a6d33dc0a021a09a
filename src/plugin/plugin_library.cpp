#include "plugin/plugin_library.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "core/case_in_progress.h"
#include "core/target_name.h"

namespace rayverify::plugin_internal {
namespace {

[[noreturn]] void fail(const std::string& problem) { throw unusable_library(problem); }

std::string text_or(const char* text, std::string fallback) { return text ? std::string(text) : fallback; }

bool is_control(unsigned char byte) { return byte < 0x20 || byte == 0x7f; }

// Control bytes (a terminal escape sequence, a newline) shown as \xNN, so that
// what a plugin says prints as one plain line.
std::string escaped(const std::string& text) {
    std::string out;
    for (const char c : text)
        out += is_control(static_cast<unsigned char>(c)) ? fmt::format("\\x{:02X}", static_cast<unsigned char>(c))
                                                          : std::string(1, c);
    return out;
}

void check_name(const std::string& name) {
    if (name.empty()) fail("the plugin's name is empty");
    if (!is_target_name(name))
        fail(fmt::format("the plugin's name '{}' must be one token without '/', '#' or control characters",
                         escaped(name)));
}

// The texts both versions describe beside the name, escaped, NULL ones
// replaced by their defaults.
void take_texts(plugin_description& d, const char* citation, const char* formula, const char* tangent_rule,
                bool reports_tangent, const std::filesystem::path& library) {
    d.citation = escaped(text_or(citation, "plugin " + library.filename().string()));
    d.formula = escaped(text_or(formula, "(not stated)"));
    d.tangent_rule = escaped(text_or(tangent_rule, reports_tangent ? "(not stated)" : "never"));
}

// Version 2: the description and the batch functions its precisions need.
void open_v2(opened_library& opened, rayverify_describe_v2_fn describe, const std::filesystem::path& library,
             const std::function<void*(const char*, bool)>& symbol) {
    const rayverify_plugin_info_v2* info = describe();
    if (!info) fail("rayverify_plugin_describe_v2() returned NULL");
    if (info->abi_version != RAYVERIFY_PLUGIN_ABI_VERSION_2)
        fail(fmt::format("rayverify_plugin_describe_v2() reports ABI version {}, expected {} "
                         "(RAYVERIFY_PLUGIN_ABI_VERSION_2)",
                         info->abi_version, RAYVERIFY_PLUGIN_ABI_VERSION_2));
    plugin_description& d = opened.description;
    d.abi = RAYVERIFY_PLUGIN_ABI_VERSION_2;
    d.name = text_or(info->name, "");
    check_name(d.name);
    d.build = escaped(text_or(info->build, ""));
    d.contract_spec = text_or(info->contract, "");
    try {
        const contract c = parse_contract(d.contract_spec);
        take_texts(d, info->citation, info->formula, info->tangent_rule, c.reports_tangent, library);
    } catch (const std::invalid_argument& e) {
        fail(fmt::format("its contract \"{}\" cannot be used: {}", escaped(d.contract_spec), e.what()));
    }
    const int known = RAYVERIFY_FLOAT | RAYVERIFY_DOUBLE;
    if ((info->precisions & known) == 0 || (info->precisions & ~known) != 0)
        fail(fmt::format("precisions = {}: expected RAYVERIFY_FLOAT, RAYVERIFY_DOUBLE or both", info->precisions));
    d.has_float = (info->precisions & RAYVERIFY_FLOAT) != 0;
    d.has_double = (info->precisions & RAYVERIFY_DOUBLE) != 0;
    // The segment entry: required under cast=segment (which answers segment
    // cases only, so the ray batch is refused there), optional otherwise (an
    // engine whose API takes two points: segment cases then reach it).
    const bool segments_only = parse_contract(d.contract_spec).takes_segment_ends;
    const bool exports_segments = symbol("rayverify_plugin_intersect_segments_double", false) ||
                                  symbol("rayverify_plugin_intersect_segments_float", false);
    if (segments_only || exports_segments) {
        if (d.has_double)
            opened.segments_double = reinterpret_cast<rayverify_segments_double_fn>(
                symbol("rayverify_plugin_intersect_segments_double", true));
        if (d.has_float)
            opened.segments_float = reinterpret_cast<rayverify_segments_float_fn>(
                symbol("rayverify_plugin_intersect_segments_float", true));
        d.has_segment_entry = true;
    }
    if (segments_only) {
        if (symbol("rayverify_plugin_intersect_batch_double", false) ||
            symbol("rayverify_plugin_intersect_batch_float", false))
            fail("its contract says cast=segment (segment cases only), but it exports "
                 "rayverify_plugin_intersect_batch_* (the ray form): leave cast out of the contract to answer both, "
                 "rays through the batch functions and segment cases through the segment entry");
        d.has_ray_batch = false;
        return;
    }
    if (d.has_double)
        opened.batch_double =
            reinterpret_cast<rayverify_batch_double_fn>(symbol("rayverify_plugin_intersect_batch_double", true));
    if (d.has_float)
        opened.batch_float =
            reinterpret_cast<rayverify_batch_float_fn>(symbol("rayverify_plugin_intersect_batch_float", true));
}

opened_library opened_here(const std::filesystem::path& library) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(library, error)) fail("no such file (expected a shared library)");
    // An absolute path, so that dlopen never searches LD_LIBRARY_PATH for a bare name.
    // RTLD_NODELETE: the library stays mapped until the process ends, so what
    // its static state holds (an engine's world, a device) is still reachable
    // then, and no static destructor of it runs in the middle of a run.
    const std::filesystem::path absolute = std::filesystem::absolute(library, error);
    dlerror();
    void* raw = dlopen(absolute.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
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
    if (const auto version =
            reinterpret_cast<rayverify_library_version_fn>(symbol("rayverify_plugin_library_version", false)))
        opened.description.library_version = escaped(text_or(version(), ""));
    if (const auto configuration = reinterpret_cast<rayverify_library_configuration_fn>(
            symbol("rayverify_plugin_library_configuration", false)))
        opened.description.library_configuration = escaped(text_or(configuration(), ""));
    if (const auto unavailable = reinterpret_cast<rayverify_unavailable_fn>(symbol("rayverify_plugin_unavailable", false)))
        if (const char* why = unavailable())
            throw unusable_library(escaped(why), unusable_library::here);
    const auto thread_safe = reinterpret_cast<rayverify_thread_safe_fn>(symbol("rayverify_plugin_thread_safe", false));
    if (const auto describe_v2 =
            reinterpret_cast<rayverify_describe_v2_fn>(symbol("rayverify_plugin_describe_v2", false))) {
        open_v2(opened, describe_v2, library, symbol);
        opened.description.thread_safe = thread_safe != nullptr && thread_safe() != 0;
        return opened;
    }
    if (!symbol("rayverify_plugin_describe", false)) {
        // Neither describe function: name both, and which one the library's other symbols point to.
        const bool batches = symbol("rayverify_plugin_intersect_batch_double", false) ||
                             symbol("rayverify_plugin_intersect_batch_float", false);
        fail(batches ? "missing symbol rayverify_plugin_describe_v2: the library exports version 2's batch functions "
                       "but no rayverify_plugin_describe_v2 (nor version 1's rayverify_plugin_describe); check its "
                       "spelling (see rayverify_plugin.h; in C++ declare it extern \"C\")"
                     : "missing symbol rayverify_plugin_describe (version 1) or rayverify_plugin_describe_v2 "
                       "(version 2) (see rayverify_plugin.h; in C++ declare it extern \"C\")");
    }
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
    check_name(d.name);
    if (info->query < RAYVERIFY_LINE_ROOTS || info->query > RAYVERIFY_NEAREST_IN_INTERVAL)
        fail(fmt::format("unknown query kind {} (RAYVERIFY_LINE_ROOTS, RAYVERIFY_NEAREST_ON_RAY, "
                         "RAYVERIFY_ANY_HIT_IN_INTERVAL or RAYVERIFY_NEAREST_IN_INTERVAL)",
                         info->query));
    d.query = info->query;
    d.assumes_unit_direction = info->assumes_unit_direction != 0;
    d.reports_tangent = info->reports_tangent != 0;
    d.clamps_to_zero = info->clamps_to_zero != 0;
    take_texts(d, info->citation, info->formula, info->tangent_rule, d.reports_tangent, library);
    d.has_float = opened.run_float != nullptr;
    d.thread_safe = thread_safe != nullptr && thread_safe() != 0;
    return opened;
}

// The IEEE default again for the calling thread, however the library left it.
struct ieee_default_on_exit {
    ~ieee_default_on_exit() { set_fp_state(ieee_default_fp_state()); }
};

}  // namespace

opened_library open_library(const std::filesystem::path& library) {
    const ieee_default_on_exit restore;
    opened_library opened = opened_here(library);
    opened.description.environment_at_load = current_fp_state();
    return opened;
}

fp_state plugin_run_environment(const plugin_description& description, const fp_environment_choice& choice) {
    if (const std::optional<fp_environment_spec> chosen = choice.for_target(description.name))
        if (const std::optional<fp_state> state = fp_state_for(*chosen)) return *state;
    return description.environment_at_load;
}

std::string plugin_environment_text(const plugin_description& description, const fp_environment_choice& choice) {
    if (const std::optional<fp_environment_spec> chosen = choice.for_target(description.name)) return chosen_fp_environment_text(*chosen);
    const fp_state& loaded = description.environment_at_load;
    if (is_ieee_default(loaded)) return {};
    fp_state ftz_daz = ieee_default_fp_state();
    if (const std::optional<fp_state> s = fp_state_for({true, true, fp_environment_spec::rounding::nearest})) ftz_daz = *s;
    return describe_fp_state(loaded) + (loaded == ftz_daz ? ", set when the library loaded (what GCC's crtfastmath.o "
                                                             "sets: linked with -ffast-math?)"
                                                           : ", set when the library loaded");
}

variant described_variant(const plugin_description& d) {
    variant v;
    v.name = d.name;
    v.citation = d.citation;
    v.formula = d.formula;
    v.thread_safe = d.thread_safe;  // rayverify_plugin.h: one thread unless rayverify_plugin_thread_safe() says otherwise
    if (!d.library_version.empty() || !d.library_configuration.empty())
        v.library = library_identity{"", d.library_version, "", d.library_configuration};
    if (d.abi == RAYVERIFY_PLUGIN_ABI_VERSION_2) {
        v.build = d.build;
        v.promises = parse_contract(d.contract_spec);  // checked by open_library
        v.promises.tangent_rule = interned_text(d.tangent_rule);
        return v;
    }
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
    v.thread_safe = d.thread_safe;  // rayverify_plugin.h: one thread unless rayverify_plugin_thread_safe() says otherwise
    return v;
}

template <class T>
corpus_case failing_case(const ray_sphere<T>& s, T tmin, T tmax, bool interval_asked) {
    if (const corpus_case* announced = case_in_progress::current()) return *announced;
    corpus_case failing;
    failing.id = "plugin-failure";
    failing.geometry = rounded_to<double>(s);
    if (interval_asked) {
        failing.tmin = tmin;
        failing.tmax = tmax;
    }
    return failing;
}
template corpus_case failing_case(const ray_sphere<float>&, float, float, bool);
template corpus_case failing_case(const ray_sphere<double>&, double, double, bool);

std::string failing_case_text() {
    const corpus_case* announced = case_in_progress::current();
    return announced ? fmt::format("on case {} ({})", announced->id, announced->source)
                     : std::string("on inputs given outside any audited case");
}

template <class T>
guarded_roots<T>::guarded_roots() {
    std::memset(cells, guard_byte, sizeof cells);
    // NaN until written, so a plugin that reports a hit without writing its roots is judged non_finite.
    roots()[0] = roots()[1] = std::numeric_limits<T>::quiet_NaN();
}

template <class T>
bool guarded_roots<T>::intact() const {
    const auto* bytes = reinterpret_cast<const unsigned char*>(cells);
    const auto clean = [](const unsigned char* p, std::size_t n) {
        return std::all_of(p, p + n, [](unsigned char b) { return b == guard_byte; });
    };
    return clean(bytes, guard * sizeof(T)) && clean(bytes + (guard + 2) * sizeof(T), guard * sizeof(T));
}

template struct guarded_roots<float>;
template struct guarded_roots<double>;

}  // namespace rayverify::plugin_internal
