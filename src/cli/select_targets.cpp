#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/shipped_libraries.h"
#include "core/fp_environment.h"
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
    // A built-in variant given an environment of its own (--fp-env): its calls
    // run in it, as the formula would where it is deployed.
    for (std::size_t i = 0; i < first_plugin; ++i)
        if (const std::optional<fp_environment_spec> spec = isolation.environment.for_target(chosen[i].name))
            if (!(*spec == fp_environment_spec{}))
                chosen[i] = in_fp_environment(std::move(chosen[i]), settable_fp_state(*spec),
                                              chosen_fp_environment_text(*spec));
    return targets_in_precisions(chosen, precisions);
}

std::vector<audit_target> targets_in_precisions(std::span<const variant> variants,
                                                const std::vector<std::string>& precisions) {
    std::vector<audit_target> targets;
    for (audit_target& t : targets_for(variants)) {
        const bool wanted = precisions.empty() ||
                            std::find(precisions.begin(), precisions.end(), precision_name(t.prec)) != precisions.end();
        if (wanted) targets.push_back(std::move(t));
    }
    return targets;
}

fp_state settable_fp_state(const fp_environment_spec& spec) {
    if (const std::optional<fp_state> state = fp_state_for(spec)) return *state;
    throw input_error("", 0, "--fp-env",
                      fmt::format("'{}' cannot be set on this machine (FTZ and DAZ are x86-64's and aarch64's; aarch64 "
                                  "flushes inputs and outputs together: ftz+daz)",
                                  fp_environment_name(spec)));
}

void add_fp_environment(fp_environment_choice& choice, const std::string& value) {
    const std::size_t equals = value.find('=');
    const std::string name = equals == std::string::npos ? std::string() : value.substr(0, equals);
    const std::string environment = equals == std::string::npos ? value : value.substr(equals + 1);
    const std::optional<fp_environment_spec> spec = parse_fp_environment(environment);
    if (!spec)
        throw input_error("", 0, "--fp-env",
                          fmt::format("'{}' is not an environment: one of {}, joined with '+' (one rounding at most)",
                                      environment, fp_environment_names));
    settable_fp_state(*spec);
    if (equals == std::string::npos) {
        if (choice.every) throw input_error("", 0, "--fp-env", "two environments for every target: give one, or TARGET=ENV");
        choice.every = *spec;
    } else if (name.empty() || !choice.by_target.emplace(name, *spec).second) {
        throw input_error("", 0, "--fp-env",
                          name.empty() ? "'=" + environment + "' names no target"
                                       : fmt::format("two environments for target '{}'", name));
    }
}

namespace {

// A target whose answers come from another process: no function of it runs here.
bool answers_elsewhere(const audit_target& t) { return !t.subject.run_float && !t.subject.run_double; }

}  // namespace

void check_fp_environment_targets(const fp_environment_choice& choice, const std::vector<audit_target>& targets) {
    for (const auto& [name, spec] : choice.by_target) {
        const auto named = std::find_if(targets.begin(), targets.end(),
                                        [&wanted = name](const audit_target& t) { return t.subject.name == wanted; });
        if (named == targets.end()) {
            std::vector<std::string> names;
            for (const audit_target& t : targets)
                if (std::find(names.begin(), names.end(), t.subject.name) == names.end()) names.push_back(t.subject.name);
            throw input_error("", 0, "--fp-env",
                              fmt::format("'{}={}' names no target of this run{}", name,
                                          fp_environment_name(spec), did_you_mean(name, names)));
        }
        if (answers_elsewhere(*named))
            throw input_error("", 0, "--fp-env",
                              fmt::format("target '{}' answers from another process (a results file, a program, a "
                                          "JavaScript engine): its floating-point environment is that process's own",
                                          name));
    }
    std::vector<std::string> noted;  // each target once, whatever its precisions
    if (choice.every)
        for (const audit_target& t : targets)
            if (answers_elsewhere(t) && std::find(noted.begin(), noted.end(), t.subject.name) == noted.end()) {
                noted.push_back(t.subject.name);
                fmt::print(stderr,
                           "note: --fp-env {} does not reach '{}', which answers from another process (its environment "
                           "is that process's own)\n",
                           fp_environment_name(*choice.every), t.subject.name);
            }
}

void add_isolation_options(CLI::App* sub, plugin_isolation& isolation) {
    sub->add_option_function<std::vector<std::string>>(
           "--fp-env",
           [&isolation](const std::vector<std::string>& values) {
               try {
                   for (const std::string& v : values) add_fp_environment(isolation.environment, v);
               } catch (const input_error& e) {
                   throw CLI::ValidationError(e.what());  // a usage error, as CLI11 reports its own (exit 2)
               }
           },
           fmt::format("Run the targets (ENV), or one target (TARGET=ENV, repeatable), in this floating-point "
                       "environment: {}, joined with '+' (ftz+daz). Default: the IEEE default, or for a plugin the "
                       "one its library set when loaded. rayverify's own arithmetic stays in the IEEE default",
                       fp_environment_names))
        ->type_name("[TARGET=]ENV");
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
