#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>

#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "report/atomic_file.h"
#include "report/audit_report.h"

namespace rayverify::cli {
namespace {

struct audit_options {
    std::vector<std::string> corpus;
    std::vector<std::string> variants;
    std::vector<std::string> precisions;
    std::string report_dir;
    std::string per_case_file;
};

// Progress on stderr, only when a person is watching it.
std::function<void(std::size_t, std::size_t)> progress_reporter() {
    if (!isatty(STDERR_FILENO)) return {};
    return [](std::size_t done, std::size_t total) {
        fmt::print(stderr, "\raudit: {}/{} cases", done, total);
        if (done == total) fmt::print(stderr, "\n");
    };
}

int run(const audit_options& options, const std::string& command_line) {
    std::vector<std::filesystem::path> paths(options.corpus.begin(), options.corpus.end());
    if (paths.empty()) paths.emplace_back(RAYVERIFY_DEFAULT_CORPUS);
    const std::vector<corpus_case> cases = read_corpus(paths);
    const std::vector<audit_target> targets = select_targets(options.variants, options.precisions);
    if (targets.empty()) throw input_error("", 0, "--precision", "no variant runs in the chosen precision");

    if (!options.report_dir.empty()) {
        std::error_code error;
        std::filesystem::create_directories(options.report_dir, error);
        if (error) throw input_error(options.report_dir, 0, "--report", "cannot create directory: " + error.message());
    }
    std::optional<atomic_file> per_case;
    if (!options.per_case_file.empty()) per_case.emplace(options.per_case_file);

    const auto write_case = [&](const audited_case& c) {
        per_case->stream() << per_case_json_line(c, targets) << '\n';
    };
    const audit_totals totals =
        run_audit(cases, targets, per_case ? std::function<void(const audited_case&)>(write_case) : nullptr,
                  progress_reporter());
    if (per_case) per_case->commit();

    const std::string table = render_summary_table(totals);
    fmt::print("{}", table);
    fmt::print("build: {} {} [{}]\n", build_json()["compiler"].get<std::string>(),
               build_json()["flags"].get<std::string>(), build_json()["build_type"].get<std::string>());

    if (!options.report_dir.empty()) {
        run_context context{command_line, {}};
        for (const auto& p : paths) context.corpus_paths.push_back(p.string());
        const std::filesystem::path dir(options.report_dir);
        write_file_atomically(dir / "report.json", audit_report_json(totals, context).dump(2) + "\n");
        write_file_atomically(dir / "summary.txt", table);
        fmt::print("report: {}\n", (dir / "report.json").string());
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
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember({"float", "double"}));
    sub->add_option("--report", options->report_dir, "Directory for report.json and summary.txt");
    sub->add_option("--per-case", options->per_case_file, "Write one JSON object per case to this file");
    return {sub, [options, command_line] { return run(*options, command_line); }};
}

}  // namespace rayverify::cli
