#include "report/scene_report.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "compare/error_figures.h"
#include "compare/judge.h"
#include "report/audit_report.h"
#include "report/schema.h"

namespace rayverify {
namespace {

// The verdict columns a query can produce (the verdict table says which): nothing else is printed.
std::vector<verdict_kind> verdicts_for(ray_query q) {
    std::vector<verdict_kind> shown;
    for (int k = 0; k < verdict_kind_count; ++k)
        if (scene_table_shows(static_cast<verdict_kind>(k), q)) shown.push_back(static_cast<verdict_kind>(k));
    return shown;
}

std::string ulp_cell(const error_summary& summary) {
    const error_statistics e = summary.statistics();
    if (e.count == 0) return "-";
    return fmt::format("{} / {} / {}", format_figure(e.median), format_figure(e.p99), format_figure(e.max));
}

std::string kind_table(const scene_audit_result& result, ray_kind kind, ray_query query) {
    const std::size_t k = static_cast<std::size_t>(kind);
    const exact_kind_figures& ex = result.exact[k];
    std::string out = fmt::format("\n{} rays — query {}: {} rays, {} hit exactly", ray_kind_name(kind),
                                  ray_query_name(query), ex.rays, ex.hits);
    if (ex.lost_to_tmin > 0)
        out += fmt::format(", {} with an exact root in (0, tmin] (hits the ray epsilon discards)", ex.lost_to_tmin);
    out += "\n";

    const std::vector<verdict_kind> columns = verdicts_for(query);
    const query_requirements needs = query_needs(query);
    std::string header = fmt::format("  {:<30}", "variant");
    for (verdict_kind v : columns) header += fmt::format(" {:>{}}", verdict_name(v), verdict_column_width(verdict_name(v)));
    header += " by_design";
    if (needs.nearest_root)
        header += fmt::format("  {:<28}", needs.far_root ? "near-root ulp med/p99/max" : "nearest ulp med/p99/max");
    if (needs.far_root) header += fmt::format("  {:<28}", "far-root ulp med/p99/max");
    if (needs.hit_point) header += fmt::format("  {:<28}", "hit-point ulp med/p99/max");
    if (needs.nearest_root) header += "  worst ray";
    out += header + "\n";
    for (const scene_target_figures& t : result.targets) {
        if (t.not_applicable) continue;
        const ray_kind_figures& f = t.by_kind[k];
        std::string row = fmt::format("  {:<30}", t.target.label());
        for (verdict_kind v : columns)
            row += fmt::format(" {:>{}}", f.verdicts[static_cast<std::size_t>(v)], verdict_column_width(verdict_name(v)));
        row += fmt::format(" {:>9}", by_design_count(f.causes));
        if (needs.nearest_root) row += fmt::format("  {:<28}", ulp_cell(f.nearest_ulp));
        if (needs.far_root) row += fmt::format("  {:<28}", ulp_cell(f.far_ulp));
        if (needs.hit_point) row += fmt::format("  {:<28}", ulp_cell(f.hit_point_ulp));
        if (needs.nearest_root && f.nearest_ulp.count > 0) row += "  " + f.nearest_ulp.max_id;
        while (!row.empty() && row.back() == ' ') row.pop_back();
        out += row + "\n";
    }
    return out;
}

nlohmann::ordered_json figures_json(const error_summary& summary) {
    const error_statistics e = summary.statistics();
    return {{"count", e.count}, {"median", printed_figure(e.median)}, {"p99", printed_figure(e.p99)}, {"max", printed_figure(e.max)}, {"max_ray", e.max_case}};
}

}  // namespace

std::string scene_audit_text(const scene& s, const scene_audit_result& result) {
    std::string out = fmt::format("scene: {} ({}), {}, directions {}\n", s.name, s.file.string(), precision_name(s.prec),
                                  s.normalise_directions ? "normalised" : "not normalised");
    if (!s.comment.empty()) out += "  " + s.comment + "\n";
    out += fmt::format("rays: {} pixels; {} primary, {} shadow, {} secondary; {} (ray, sphere) pairs judged exactly\n",
                       result.pixels, result.exact[0].rays, result.exact[1].rays, result.exact[2].rays, result.pairs);
    for (const ray_kind kind : every_ray_kind) {
        const ray_kind_settings& settings = s.settings(kind);
        if (settings.enabled && result.exact[static_cast<std::size_t>(kind)].rays > 0)
            out += kind_table(result, kind, settings.query);
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

nlohmann::ordered_json scene_report_json(const scene& s, const scene_audit_result& result, const std::string& command) {
    nlohmann::ordered_json targets = nlohmann::ordered_json::array();
    for (const scene_target_figures& t : result.targets) {
        nlohmann::ordered_json entry = {{"target", t.target.label()}};
        if (t.not_applicable) {
            entry["not_applicable"] = *t.not_applicable;
            targets.push_back(entry);
            continue;
        }
        for (const ray_kind kind : every_ray_kind) {
            const ray_kind_settings& settings = s.settings(kind);
            if (!settings.enabled) continue;
            const ray_kind_figures& f = t.by_kind[static_cast<std::size_t>(kind)];
            const query_requirements needs = query_needs(settings.query);
            nlohmann::ordered_json k = {{"query", ray_query_name(settings.query)}, {"rays", f.rays}};
            for (verdict_kind v : verdicts_for(settings.query))
                k["verdicts"][std::string(verdict_name(v))] = f.verdicts[static_cast<std::size_t>(v)];
            for (int c = 0; c < disagreement_cause_count; ++c)
                if (f.causes[static_cast<std::size_t>(c)] > 0)
                    k["causes"][std::string(cause_name(static_cast<disagreement_cause>(c)))] =
                        f.causes[static_cast<std::size_t>(c)];
            if (needs.nearest_root) k["nearest_ulp"] = figures_json(f.nearest_ulp);
            if (needs.far_root) k["far_ulp"] = figures_json(f.far_ulp);
            if (needs.hit_point) k["hit_point_ulp"] = figures_json(f.hit_point_ulp);
            entry[ray_kind_name(kind)] = k;
        }
        targets.push_back(entry);
    }
    nlohmann::ordered_json exact;
    for (const ray_kind kind : every_ray_kind) {
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

}  // namespace rayverify
