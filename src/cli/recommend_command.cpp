// `rayverify recommend --scene FILE [--budget max-ulp=X,max-wrong=N]`: for
// each ray kind the scene casts, the cheapest variant (by time measured on the
// scene's own rays) that meets the accuracy budget on them, the runner-up,
// and the figures that decided. Exit 1 when some kind has no such variant.
#include <fmt/format.h>

#include <memory>

#include "compare/error_figures.h"
#include "bench/recommend.h"
#include "cli/commands.h"
#include "compare/judge.h"
#include "core/input_error.h"
#include "plugin/plugin_loader.h"
#include "report/audit_report.h"

namespace rayverify::cli {
namespace {

struct recommend_options {
    std::string scene_file;
    std::string budget = "max-ulp=4,max-wrong=0";
    std::vector<std::string> variants, plugins;
    plugin_isolation isolation;
    int repetitions = 9;
    double min_time = 0.01;
};

void print_kind(const bench::kind_recommendation& k, const bench::recommend_budget& budget) {
    fmt::print("\n{} rays ({} rays, query {}):\n", ray_kind_name(k.kind), k.rays, ray_query_name(k.query));
    fmt::print("  {:<26} {:>9} {:>17} {:>6} {:>7} {:>6} {:>9}  {}\n", "variant", "ns/ray", "(min..max)", "wrong",
               "f_miss", "f_hit", "max_ulp", "verdict");
    for (std::size_t i = 0; i < k.candidates.size(); ++i) {
        const bench::recommend_candidate& c = k.candidates[i];
        if (c.not_applicable) continue;
        const char* mark = k.winner == i ? "  <- recommended" : (k.runner_up == i ? "  <- runner-up" : "");
        fmt::print("  {:<26} {:>9.2f} {:>17} {:>6} {:>7} {:>6} {:>9}  {}{}\n", c.variant, c.ns_per_ray,
                   fmt::format("({:.2f}..{:.2f})", c.ns_min, c.ns_max), c.wrong, c.false_miss, c.false_hit,
                   format_figure(c.max_ulp), c.verdict, mark);
    }
    for (const bench::recommend_candidate& c : k.candidates)
        if (c.not_applicable) fmt::print("  not applicable: {}: {}\n", c.variant, *c.not_applicable);

    if (!k.winner) {
        fmt::print("  no variant meets the budget ({}) for {} rays\n", budget.describe(), ray_kind_name(k.kind));
        return;
    }
    const bench::recommend_candidate& w = k.candidates[*k.winner];
    fmt::print("  recommended for {} rays: {} — {:.2f} ns/ray, {} wrong of {}, max root error {} ulp{}\n",
               ray_kind_name(k.kind), w.variant, w.ns_per_ray, w.wrong, w.rays, format_figure(w.max_ulp),
               w.exact_decisions ? "; its decisions are exact for every input (robust_sphere.h)" : "");
    // Why the cheaper ones lost.
    for (std::size_t i = 0; i < *k.winner; ++i) {
        const bench::recommend_candidate& c = k.candidates[i];
        const std::string why = c.meets_budget ? "no wrong ray here, but nothing rules one out on other rays and "
                                                 "the budget allows none"
                                               : c.verdict;
        fmt::print("    cheaper but rejected: {} ({:.2f} ns/ray): {}\n", c.variant, c.ns_per_ray, why);
    }
    if (k.runner_up) {
        const bench::recommend_candidate& r = k.candidates[*k.runner_up];
        fmt::print("    runner-up: {} — {:.2f} ns/ray ({:.2f}× the recommended), {} wrong, max root error {} ulp\n",
                   r.variant, r.ns_per_ray, r.ns_per_ray / w.ns_per_ray, r.wrong, format_figure(r.max_ulp));
    } else {
        fmt::print("    runner-up: none (no other variant meets the budget)\n");
    }
}

int run(const recommend_options& options) {
    // Its timings and choices are of the code as compiled, in the IEEE default.
    if (!options.isolation.environment.empty())
        throw input_error("", 0, "--fp-env",
                          "recommend times and judges its targets in the IEEE default; --fp-env is for audit, gate, "
                          "explain, hunt and render");
    const scene s = read_scene(options.scene_file);
    const bench::recommend_budget budget = bench::parse_budget(options.budget);

    std::vector<variant> variants;
    for (const std::string& name : options.variants) {
        const variant* v = find_builtin_variant(name);
        if (!v) throw input_error("", 0, "--variant", fmt::format("unknown variant '{}'", name));
        variants.push_back(*v);
    }
    if (options.variants.empty() && options.plugins.empty())
        variants.assign(builtin_variants().begin(), builtin_variants().end());
    for (const std::string& path : options.plugins) variants.push_back(load_plugin(path, options.isolation));

    const std::vector<scene_ray> rays = generate_rays(s);
    bench::timing_options timing;
    timing.repetitions = options.repetitions;
    timing.min_time_s = options.min_time;
    const bench::recommendation r = bench::recommend(s, rays, variants, budget, timing);

    fmt::print("recommend: scene {} ({}, directions {}normalised), {} rays; budget: {}\n", r.scene_name,
               precision_name(r.prec), r.normalised ? "" : "not ", rays.size(), budget.describe());
    fmt::print("time: median CPU ns per ray over {} repetitions, each ray against every sphere it can meet, the "
               "intersector inlined; errors: every ray judged by the exact oracle at the level of its query\n",
               options.repetitions);
    for (const bench::kind_recommendation& k : r.kinds) print_kind(k, budget);
    fmt::print("\nbuild: {}; CPU: {}\n", build_summary(), bench::cpu_model());
    return r.all_met() ? exit_ok : exit_findings;
}

}  // namespace

command add_recommend_command(CLI::App& app) {
    auto options = std::make_shared<recommend_options>();
    auto* sub = app.add_subcommand(
        "recommend",
        "For each ray kind of a scene, the cheapest variant (time measured on the scene's own rays) that meets an "
        "accuracy budget on them, with the runner-up and the figures that decided. Exit 1 when some ray kind has no "
        "variant within the budget.");
    sub->add_option("--scene", options->scene_file, "Scene file (corpus/scenes/README.md)")->required();
    sub->add_option("--budget", options->budget,
                    "Accuracy budget: max-ulp=X (root error of agreeing rays, in ulps) and max-wrong=N (rays whose "
                    "answer differs from the exact one), comma separated")
        ->capture_default_str();
    sub->add_option("--variant", options->variants, "Only these built-in variants (default: all)");
    sub->add_option("--plugin", options->plugins, "Also a plugin (rayverify_plugin.h), timed through its function");
    // Isolated, a plugin's time includes the round trip to its process.
    add_isolation_options(sub, options->isolation);
    sub->add_option("--repetitions", options->repetitions, "Timing repetitions per variant")
        ->check(whole_number(1, 1000))
        ->capture_default_str();
    sub->add_option("--min-time", options->min_time, "Seconds per repetition")
        ->check(finite_number(0, 3600, true))
        ->capture_default_str();
    return {sub, [options] { return run(*options); }};
}

}  // namespace rayverify::cli
