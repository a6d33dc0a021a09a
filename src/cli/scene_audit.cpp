// `rayverify audit --scene FILE`: the scene's rays, judged at the level each
// ray's query needs (scene/scene_audit.h), printed as one table per ray kind
// and written as scene_report.json (report/scene_report.h).
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/input_error.h"
#include "report/audit_report.h"
#include "report/json_line.h"
#include "report/scene_report.h"
#include "scene/scene.h"
#include "scene/scene_audit.h"

namespace rayverify::cli {

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
    check_fp_environment_targets(isolation.environment, targets);
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
    require_clauses(targets, request.results);

    run_outputs outputs;  // declared before the work; committed after it
    declare_inputs(outputs, {request.scene_file}, "--scene");
    declare_inputs(outputs, {request.plugins.begin(), request.plugins.end()}, "--plugin");
    declare_results_inputs(outputs, request.results);
    output_file* report = nullptr;
    if (!request.report_dir.empty()) {
        outputs.directory(request.report_dir, "--report");
        report = &outputs.file(std::filesystem::path(request.report_dir) / "scene_report.json", "--report");
    }

    const scene_audit_result result = audit_scene(s, targets, {}, request.route);  // the rays streamed

    const std::string text = scene_audit_text(s, result);
    fmt::print("{}", text);
    fmt::print("build: {}\n", build_summary());
    if (report != nullptr) {
        report->stream() << json_text(scene_report_json(s, result, recorded_command(request.command_line)), 2) << '\n';
        fmt::print("report: {}\n", (std::filesystem::path(request.report_dir) / "scene_report.json").string());
    }
    check_standard_output();
    outputs.commit();
    bool findings = false;
    for (const scene_target_figures& t : result.targets) findings = findings || (!t.not_applicable && t.disagreements() > 0);
    return findings ? exit_findings : exit_ok;
}

}  // namespace rayverify::cli
