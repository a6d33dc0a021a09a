// `rayverify audit --scene FILE`: the scene's rays, judged at the level each
// ray's query needs (scene/scene_audit.h), printed as one table per ray kind.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/input_error.h"
#include "report/audit_report.h"
#include "report/schema.h"
#include "scene/scene.h"
#include "scene/scene_audit.h"

namespace rayverify::cli {
namespace {

// The verdict columns a query can produce: nothing else is printed.
std::vector<verdict_kind> verdicts_for(ray_query q) {
    std::vector<verdict_kind> shown;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (scene_table_shows(static_cast<verdict_kind>(k), q)) shown.push_back(static_cast<verdict_kind>(k));
    return shown;
}

// How many of the disagreements the formula makes by design (the clamp's light leaks among them).
std::size_t by_design(const ray_kind_figures& f) {
    std::size_t n = 0;
    for (int c = 0; c < disagreement_cause_count; ++c)
        if (is_by_design(static_cast<disagreement_cause>(c))) n += f.causes[static_cast<std::size_t>(c)];
    return n;
}

std::size_t column_width(std::string_view name) { return std::max<std::size_t>(6, name.size()); }

const ray_kind_settings& settings_of(const scene& s, ray_kind k) {
    return k == ray_kind::primary ? s.primary : k == ray_kind::shadow ? s.shadow : s.secondary;
}

std::string ulp_cell(const error_summary& summary) {
    const error_statistics e = summary.statistics();
    if (e.count == 0) return "-";
    return fmt::format("{:.3g} / {:.3g} / {:.3g}", e.median, e.p99, e.max);
}

std::string render_scene_tables(const scene& s, const scene_audit_result& result) {
    std::string out;
    for (ray_kind kind : {ray_kind::primary, ray_kind::shadow, ray_kind::secondary}) {
        const ray_kind_settings& settings = settings_of(s, kind);
        const std::size_t k = static_cast<std::size_t>(kind);
        if (!settings.enabled || result.exact[k].rays == 0) continue;
        const exact_kind_figures& ex = result.exact[k];
        out += fmt::format("\n{} rays — query {}: {} rays, {} hit exactly", ray_kind_name(kind),
                           ray_query_name(settings.query), ex.rays, ex.hits);
        if (ex.lost_to_tmin > 0)
            out += fmt::format(", {} with an exact root in (0, tmin] (hits the ray epsilon discards)", ex.lost_to_tmin);
        out += "\n";

        const std::vector<verdict_kind> columns = verdicts_for(settings.query);
        const bool nearest = settings.query != ray_query::any_hit;
        const bool far = settings.query == ray_query::both_roots;
        const bool point = settings.query == ray_query::hit_point_normal;
        std::string header = fmt::format("  {:<30}", "variant");
        for (verdict_kind v : columns) header += fmt::format(" {:>{}}", verdict_name(v), column_width(verdict_name(v)));
        header += " by_design";
        if (nearest) header += fmt::format("  {:<28}", far ? "near-root ulp med/p99/max" : "nearest ulp med/p99/max");
        if (far) header += fmt::format("  {:<28}", "far-root ulp med/p99/max");
        if (point) header += fmt::format("  {:<28}", "hit-point ulp med/p99/max");
        if (nearest) header += "  worst ray";
        out += header + "\n";
        for (const scene_target_figures& t : result.targets) {
            if (t.not_applicable) continue;
            const ray_kind_figures& f = t.by_kind[k];
            std::string row = fmt::format("  {:<30}", t.target.label());
            for (verdict_kind v : columns)
                row += fmt::format(" {:>{}}", f.verdicts[static_cast<std::size_t>(v)], column_width(verdict_name(v)));
            row += fmt::format(" {:>9}", by_design(f));
            if (nearest) row += fmt::format("  {:<28}", ulp_cell(f.nearest_ulp));
            if (far) row += fmt::format("  {:<28}", ulp_cell(f.far_ulp));
            if (point) row += fmt::format("  {:<28}", ulp_cell(f.hit_point_ulp));
            if (nearest && f.nearest_ulp.count > 0) row += "  " + f.nearest_ulp.max_id;
            while (!row.empty() && row.back() == ' ') row.pop_back();
            out += row + "\n";
        }
    }
    bool any_skipped = false;
    for (const scene_target_figures& t : result.targets) {
        if (!t.not_applicable) continue;
        if (!any_skipped) out += "\nnot applicable to this scene:\n";
        any_skipped = true;
        out += fmt::format("  {:<30} {}\n", t.target.label(), *t.not_applicable);
    }
    return out;
}

nlohmann::ordered_json figures_json(const error_summary& summary) {
    const error_statistics e = summary.statistics();
    return {{"count", e.count}, {"median", e.median}, {"p99", e.p99}, {"max", e.max}, {"max_ray", e.max_case}};
}

nlohmann::ordered_json scene_report_json(const scene& s, const scene_audit_result& result, const std::string& command) {
    nlohmann::ordered_json targets = nlohmann::ordered_json::array();
    for (const scene_target_figures& t : result.targets) {
        nlohmann::ordered_json entry = {{"target", t.target.label()}};
        if (t.not_applicable) {
            entry["not_applicable"] = *t.not_applicable;
            targets.push_back(entry);
            continue;
        }
        for (ray_kind kind : {ray_kind::primary, ray_kind::shadow, ray_kind::secondary}) {
            const ray_kind_settings& settings = settings_of(s, kind);
            if (!settings.enabled) continue;
            const ray_kind_figures& f = t.by_kind[static_cast<std::size_t>(kind)];
            nlohmann::ordered_json k = {{"query", ray_query_name(settings.query)}, {"rays", f.rays}};
            for (verdict_kind v : verdicts_for(settings.query))
                k["verdicts"][std::string(verdict_name(v))] = f.verdicts[static_cast<std::size_t>(v)];
            for (int c = 0; c < disagreement_cause_count; ++c)
                if (f.causes[static_cast<std::size_t>(c)] > 0)
                    k["causes"][std::string(cause_name(static_cast<disagreement_cause>(c)))] =
                        f.causes[static_cast<std::size_t>(c)];
            if (settings.query != ray_query::any_hit) k["nearest_ulp"] = figures_json(f.nearest_ulp);
            if (settings.query == ray_query::both_roots) k["far_ulp"] = figures_json(f.far_ulp);
            if (settings.query == ray_query::hit_point_normal) k["hit_point_ulp"] = figures_json(f.hit_point_ulp);
            entry[ray_kind_name(kind)] = k;
        }
        targets.push_back(entry);
    }
    nlohmann::ordered_json exact;
    for (ray_kind kind : {ray_kind::primary, ray_kind::shadow, ray_kind::secondary}) {
        const exact_kind_figures& e = result.exact[static_cast<std::size_t>(kind)];
        exact[ray_kind_name(kind)] = {{"rays", e.rays}, {"hits", e.hits}, {"lost_to_tmin", e.lost_to_tmin}};
    }
    return {{"schema_version", schema_version::scene_report},
            {"format", "rayverify-scene-audit-1"},
            {"build", build_json()},
            {"command", command},
            {"scene", {{"name", s.name}, {"file", s.file.string()}, {"comment", s.comment},
                       {"precision", precision_name(s.prec)}, {"normalise_directions", s.normalise_directions}}},
            {"pixels", result.pixels},
            {"pairs", result.pairs},
            {"exact", exact},
            {"targets", targets}};
}

}  // namespace

// One target per chosen variant, in the scene's precision; a variant that
// does not run in it is kept so the report can say why it is not applicable.
std::vector<audit_target> scene_audit_targets(const scene& s, const std::vector<std::string>& variant_names,
                                              const std::vector<std::string>& plugin_paths,
                                              const plugin_isolation& isolation,
                                              const std::vector<std::string>& engine_names) {
    std::vector<audit_target> targets;
    for (const audit_target& t : select_targets(variant_names, plugin_paths, {}, isolation, engine_names)) {
        const bool seen = std::any_of(targets.begin(), targets.end(),
                                      [&](const audit_target& u) { return u.subject.name == t.subject.name; });
        if (!seen) targets.push_back({t.subject, s.prec});
    }
    return targets;
}

int run_scene_audit(const scene_audit_request& request) {
    if (!request.precisions.empty())
        throw input_error("", 0, "--precision", "a scene fixes its precision (its \"precision\" field); drop --precision");
    const scene s = read_scene(request.scene_file);
    const std::vector<audit_target> outside = outside_targets(
        request.results, {},
        [&](const case_sink& add) {
            const std::vector<corpus_case> cases = scene_cases(s);
            for (const corpus_case& c : cases) add(c);
            return fingerprint_of(cases);
        },
        s.prec);
    std::vector<audit_target> targets;
    if (outside.empty() || !request.variants.empty() || !request.plugins.empty() || !request.results.engines.empty())
        targets = scene_audit_targets(s, request.variants, request.plugins, request.isolation, request.results.engines);
    append_outside_targets(targets, outside);

    run_outputs outputs;  // declared before the work; committed after it
    declare_inputs(outputs, {request.scene_file}, "--scene");
    declare_inputs(outputs, {request.plugins.begin(), request.plugins.end()}, "--plugin");
    declare_results_inputs(outputs, request.results);
    output_file* report = nullptr;
    if (!request.report_dir.empty()) {
        outputs.directory(request.report_dir, "--report");
        report = &outputs.file(std::filesystem::path(request.report_dir) / "scene_report.json", "--report");
    }

    const scene_audit_result result = audit_scene(s, targets);  // the rays streamed

    std::size_t counts[3] = {result.exact[0].rays, result.exact[1].rays, result.exact[2].rays};
    std::string text = fmt::format("scene: {} ({}), {}, directions {}\n", s.name, s.file.string(), precision_name(s.prec),
                                   s.normalise_directions ? "normalised" : "not normalised");
    if (!s.comment.empty()) text += "  " + s.comment + "\n";
    text += fmt::format("rays: {} pixels; {} primary, {} shadow, {} secondary; {} (ray, sphere) pairs judged exactly\n",
                        result.pixels, counts[0], counts[1], counts[2], result.pairs);
    text += render_scene_tables(s, result);
    fmt::print("{}", text);
    fmt::print("build: {}\n", build_summary());
    if (report != nullptr) {
        report->stream() << scene_report_json(s, result, recorded_command(request.command_line)).dump(2) << '\n';
        fmt::print("report: {}\n", (std::filesystem::path(request.report_dir) / "scene_report.json").string());
    }
    check_standard_output();
    outputs.commit();
    bool findings = false;
    for (const scene_target_figures& t : result.targets) findings = findings || (!t.not_applicable && t.disagreements() > 0);
    return findings ? exit_findings : exit_ok;
}

}  // namespace rayverify::cli
