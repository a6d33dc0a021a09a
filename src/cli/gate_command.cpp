#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/app.h"
#include "cli/commands.h"
#include "compare/gate.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "report/gate_report.h"

namespace rayverify::cli {
namespace {

struct gate_options {
    std::string baseline;
    std::vector<std::string> corpus;
    std::vector<std::string> variants;
    std::vector<std::string> plugins;
    plugin_isolation isolation;
    std::vector<std::string> precisions;
    std::string junit;
    bool update = false;
    std::size_t examples = 3;
    unsigned threads = 0;  // 0: every hardware thread
    results_options results;
    double tolerance = default_figure_tolerance;
    std::vector<std::string> allow_missing;  // families, variants or targets of the baseline the run may lack
};

int run(const gate_options& options) {
    const std::filesystem::path baseline_path(options.baseline);
    std::error_code error;
    const bool exists = std::filesystem::exists(baseline_path, error);
    if (!exists && !options.update)
        throw input_error(options.baseline, 0, "--baseline",
                          "no such baseline; create it with `rayverify gate --baseline FILE --update`");
    const baseline base =
        exists ? parse_baseline(options.baseline, read_text_file(baseline_path, "--baseline")) : new_baseline();

    std::vector<std::filesystem::path> paths(options.corpus.begin(), options.corpus.end());
    if (paths.empty()) paths.emplace_back(default_corpus());
    // The outputs, declared before the work: --update rewrites the baseline in place, --junit may not overwrite an input.
    run_outputs outputs;
    declare_inputs(outputs, paths, options.corpus.empty() ? "the default corpus" : "--corpus");
    declare_inputs(outputs, {options.plugins.begin(), options.plugins.end()}, "--plugin");
    if (!options.update) declare_inputs(outputs, {baseline_path}, "--baseline");
    declare_results_inputs(outputs, options.results);
    output_file* updated = options.update ? &outputs.file(baseline_path, "--baseline") : nullptr;
    output_file* junit = !options.update && !options.junit.empty() ? &outputs.file(options.junit, "--junit") : nullptr;
    corpus_reading reading;
    const std::vector<corpus_case> cases = read_corpus(paths, &reading);
    terminal::note("gate: read " + reading.text());
    const std::vector<audit_target> outside = outside_targets(options.results, options.precisions, [&](const case_sink& add) {
        for (const corpus_case& c : cases) add(c);
        return fingerprint_of(cases);
    });
    const std::vector<audit_target> targets =
        targets_with_results(options.variants, options.plugins, options.precisions, options.isolation, options.results,
                             outside);
    if (targets.empty()) throw input_error("", 0, "--precision", "no variant runs in the chosen precision");

    const unsigned threads = thread_count(options.threads);
    const gate_run run =
        run_gate(cases, targets, base, options.examples, threads, options.tolerance, options.allow_missing);
    if (updated != nullptr) {
        updated->stream() << format_baseline(updated_baseline(base, run.current, run.configurations, run.contracts));
        std::size_t changed = 0;
        for (const figure_change& c : run.result.changes) changed += c.kind == change_kind::new_entry ? 0 : 1;
        fmt::print("gate: {} {}: {} figures of {} target(s) over {} cases; {} changed, {} new\n",
                   exists ? "updated" : "created", options.baseline, run.current.size(), targets.size(),
                   cases.size(), changed, run.result.changes.size() - changed);
        check_standard_output();
        outputs.commit();
        return exit_ok;
    }
    fmt::print("{}", terminal::coloured_verdicts(render_gate_text(run, cases)));
    if (junit != nullptr) junit->stream() << render_junit(run, cases);
    check_standard_output();
    outputs.commit();
    return run.result.passed() ? exit_ok : exit_findings;
}

}  // namespace

std::string read_text_file(const std::filesystem::path& path, const std::string& field) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error))
        throw input_error(path.string(), 0, field, "is a directory, not a baseline file");
    if (std::filesystem::exists(path, error) && !std::filesystem::is_regular_file(path, error))
        throw input_error(path.string(), 0, field, "is not a regular file (a FIFO, a device or a socket)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error(path.string(), 0, field, "cannot open for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw input_error(path.string(), 0, field, "read error");
    return text.str();
}

command add_gate_command(CLI::App& app) {
    auto options = std::make_shared<gate_options>();
    auto* sub = app.add_subcommand(
        "gate", "Audit, then compare every figure (per variant, precision and family: each disagreement count, "
                "max and p99 ULP error of each root) with a reviewed baseline. Exit 1 when a figure is worse "
                "than the baseline's policy allows; better figures pass and say the baseline can be tightened.");
    sub->add_option("--baseline", options->baseline, "Baseline file (text, one figure a line)")->required();
    sub->add_option("--allow-missing", options->allow_missing,
                    "A family, variant or target of the baseline this run may leave out (repeatable); without it "
                    "one that is absent fails the gate")
        ->type_name("NAME");
    sub->add_option("--corpus", options->corpus,
                    "Corpus file (.txt or .csv) or directory of them; repeatable. Default: the shipped corpus");
    sub->add_option("--variant", options->variants, "Built-in variant to gate (repeatable; default: all)");
    sub->add_option("--plugin", options->plugins, "Shared library implementing rayverify_plugin.h (repeatable)");
    add_isolation_options(sub, options->isolation);
    add_results_options(sub, options->results);
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember(precision_names()));
    sub->add_option("--junit", options->junit, "Also write JUnit XML (a test case per variant and family)");
    sub->add_flag("--update", options->update,
                  "Rewrite the baseline with this run's figures (comments and policy lines are kept)");
    sub->add_option("--examples", options->examples, "Cases shown as corpus lines per failing figure")
        ->check(whole_number(0, 1000))
        ->capture_default_str();
    sub->add_option("--threads", options->threads,
                    "Threads auditing cases (default: every hardware thread); the result is the same for any number")
        ->check(whole_number(1, 4096));
    add_tolerance_option(sub, options->tolerance);
    return {sub, [options] { return run(*options); }};
}

}  // namespace rayverify::cli
