#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>

#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "report/atomic_file.h"
#include "report/audit_report.h"
#include "report/markdown_report.h"
#include "report/stability_report.h"

namespace rayverify::cli {
namespace {

struct audit_options {
    std::vector<std::string> corpus;
    std::vector<std::string> variants;
    std::vector<std::string> plugins;
    std::vector<std::string> precisions;
    std::string report_dir;
    std::string per_case_file;
    bool plots = false;
};

// Progress on stderr, only when a person is watching it.
std::function<void(std::size_t, std::size_t)> progress_reporter() {
    if (!isatty(STDERR_FILENO)) return {};
    return [](std::size_t done, std::size_t total) {
        fmt::print(stderr, "\raudit: {}/{} cases", done, total);
        if (done == total) fmt::print(stderr, "\n");
    };
}

// An output path naming an existing directory fails before the audit, not at the rename after it.
void refuse_directory(const std::filesystem::path& path, const char* option) {
    std::error_code error;
    if (!path.empty() && std::filesystem::is_directory(path, error))
        throw input_error(path.string(), 0, option, "is a directory, expected a file to write");
}

int run(const audit_options& options, const std::string& command_line) {
    std::vector<std::filesystem::path> paths(options.corpus.begin(), options.corpus.end());
    if (paths.empty()) paths.emplace_back(RAYVERIFY_DEFAULT_CORPUS);
    const std::vector<corpus_case> cases = read_corpus(paths);
    const std::vector<audit_target> targets = select_targets(options.variants, options.plugins, options.precisions);
    if (targets.empty()) throw input_error("", 0, "--precision", "no variant runs in the chosen precision");

    // Every output is opened (as a temporary) before the audit and committed
    // only once all of them are complete: an error leaves no output behind.
    const std::filesystem::path report_dir(options.report_dir);
    const std::filesystem::path report_json_path = report_dir / "report.json", summary_path = report_dir / "summary.txt";
    refuse_directory(options.per_case_file, "--per-case");
    if (!options.report_dir.empty()) {
        refuse_directory(report_json_path, "--report");
        refuse_directory(summary_path, "--report");
    }
    std::optional<atomic_file> per_case, report_json, summary;
    if (!options.per_case_file.empty()) per_case.emplace(options.per_case_file);
    if (!options.report_dir.empty()) {
        std::error_code error;
        std::filesystem::create_directories(options.report_dir, error);
        if (error) throw input_error(options.report_dir, 0, "--report", "cannot create directory: " + error.message());
        report_json.emplace(report_json_path);
        summary.emplace(summary_path);
    }

    // Stability (compare/stability.h) per case, for the per-case lines, the report and its plots.
    stability_accumulator stability(targets);
    std::vector<std::string> labels;
    for (const audit_target& t : targets) labels.push_back(t.label());
    case_points points(targets, labels);
    const auto on_case = [&](const audited_case& c) {
        const case_stability s = assess_case(c, targets);
        stability.add(c, s);
        if (report_json) points.add(c, s);
        if (!per_case) return;
        nlohmann::ordered_json line = per_case_json(c, targets);
        add_stability_fields(line, s, targets);
        per_case->stream() << line.dump() << '\n';
    };
    const audit_totals totals = run_audit(cases, targets, on_case, progress_reporter());

    const std::string table = render_summary_table(totals);
    nlohmann::ordered_json report;
    if (report_json) {
        run_context context{command_line, {}};
        for (const auto& p : paths) context.corpus_paths.push_back(p.string());
        report = audit_report_json(totals, context);
        report["stability"] = stability_json(totals, stability.finish());
        report["case_points"] = points.to_json();
        report_json->stream() << report.dump(2) << '\n';
        summary->stream() << table;
    }
    for (std::optional<atomic_file>* output : {&per_case, &report_json, &summary})
        if (*output) (*output)->commit();

    fmt::print("{}", table);
    fmt::print("build: {} {} [{}]\n", build_json()["compiler"].get<std::string>(),
               build_json()["flags"].get<std::string>(), build_json()["build_type"].get<std::string>());
    if (report_json) {
        // report.md and the plots render the committed report.json.
        const plot_outcome plots = write_report_bundle(report_dir, report, options.plots);
        fmt::print("report: {}\n", report_json_path.string());
        fmt::print("plots: {}\n", plots.message);
    }
    bool findings = false;
    for (const target_tally& t : totals.overall) findings = findings || t.disagreements() > 0;
    return findings ? exit_findings : exit_ok;
}

}  // namespace

command add_audit_command(CLI::App& app, const std::string& command_line) {
    auto options = std::make_shared<audit_options>();
    auto* sub = app.add_subcommand("audit", "Run intersectors beside the exact oracle over a corpus and report "
                                            "every disagreement and error statistic. Exit 1 when any variant "
                                            "disagrees with the exact answer on some case.");
    sub->add_option("--corpus", options->corpus,
                    "Corpus file (.txt or .csv) or directory of them; repeatable. Default: the shipped corpus");
    sub->add_option("--variant", options->variants, "Variant to audit (repeatable; default: all)");
    sub->add_option("--plugin", options->plugins,
                    "Shared library implementing rayverify_plugin.h, audited as a variant (repeatable)");
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember({"float", "double"}));
    sub->add_option("--report", options->report_dir,
                    "Directory for report.json, summary.txt, report.md and the PNG plots");
    sub->add_flag("--plots", options->plots,
                  "With --report: also draw the PNG plots (tools/plot_report.py, matplotlib; takes seconds)");
    sub->add_option("--per-case", options->per_case_file, "Write one JSON object per case to this file");
    return {sub, [options, command_line] { return run(*options, command_line); }};
}

}  // namespace rayverify::cli
