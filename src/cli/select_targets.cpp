#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/shipped_libraries.h"
#include "core/input_error.h"
#include "core/spelling.h"
#include "plugin/plugin_loader.h"

namespace rayverify::cli {

precision named_precision(std::string_view name) {
    if (const std::optional<precision> p = precision_from_name(name)) return *p;
    throw input_error("", 0, "--precision", fmt::format("'{}' is neither float nor double", name));
}

std::vector<std::string> precision_names() {
    std::vector<std::string> names;
    for (const precision p : every_precision) names.emplace_back(precision_name(p));
    return names;
}

std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& precisions) {
    return select_targets(variant_names, {}, precisions);
}

std::vector<audit_target> select_targets(const std::vector<std::string>& variant_names,
                                         const std::vector<std::string>& plugin_paths,
                                         const std::vector<std::string>& precisions,
                                         const plugin_isolation& isolation,
                                         const std::vector<std::string>& engine_names) {
    std::vector<variant> chosen;
    if (variant_names.empty() && plugin_paths.empty() && engine_names.empty()) {
        const auto all = builtin_variants();
        chosen.assign(all.begin(), all.end());
    }
    for (const std::string& name : variant_names) {
        const variant* v = find_builtin_variant(name);
        if (!v) {
            std::string known;
            std::vector<std::string> names;
            for (const variant& b : builtin_variants()) {
                known += (known.empty() ? "" : ", ") + b.name;
                names.push_back(b.name);
            }
            throw input_error("", 0, "--variant",
                              fmt::format("unknown variant '{}'{}; known: {}", name, did_you_mean(name, names), known));
        }
        chosen.push_back(*v);
    }
    const std::size_t first_plugin = chosen.size();
    for (const std::string& path : plugin_paths) chosen.push_back(load_plugin(path, isolation));
    for (std::size_t i = first_plugin; i < chosen.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (chosen[i].name == chosen[j].name)
                throw input_error(plugin_paths[i - first_plugin], 0, "--plugin",
                                  fmt::format("two targets named '{}' (a plugin's name must differ from the "
                                              "built-in variants and other plugins)",
                                              chosen[i].name));
    // The engines' libraries called through plugins (the others run as programs: outside_targets).
    for (const shipped_library& lib : requested_libraries(engine_names)) {
        if (lib.how != shipped_library::runner::plugin) continue;
        variant v = load_plugin(lib.plugin, isolation);
        if (v.name != lib.name)
            throw input_error(lib.plugin.string(), 0, "--engine",
                              fmt::format("the plugin of engine library '{}' calls itself '{}'", lib.name, v.name));
        if (std::any_of(chosen.begin(), chosen.end(), [&](const variant& c) { return c.name == v.name; }))
            throw input_error("", 0, "--engine", fmt::format("two targets named '{}'", v.name));
        v.library = lib.identity;
        chosen.push_back(std::move(v));
    }
    std::vector<audit_target> targets;
    for (audit_target& t : targets_for(chosen)) {
        const bool wanted = precisions.empty() ||
                            std::find(precisions.begin(), precisions.end(), precision_name(t.prec)) != precisions.end();
        if (wanted) targets.push_back(std::move(t));
    }
    return targets;
}

void add_isolation_options(CLI::App* sub, plugin_isolation& isolation) {
    CLI::Option* isolate =
        sub->add_flag("--isolate", isolation.child_process,
                      "Run each plugin in a child process of its own: a plugin that crashes, exits or hangs stops "
                      "the run with an error naming the case and giving it as a corpus line (exit 2), and no output "
                      "is written");
    sub->add_option("--plugin-timeout", isolation.timeout_seconds,
                    "With --isolate: seconds a plugin may take over one call (or over loading) before it is killed "
                    "and the case named")
        ->check(finite_number(0.001, 86400))
        ->needs(isolate)
        ->capture_default_str();
}

}  // namespace rayverify::cli
