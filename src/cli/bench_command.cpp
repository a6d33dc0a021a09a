// rayverify bench: run time of every variant in float, double and long double
// beside its accuracy and stability, and the exact oracle's own cost.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "bench/far_sphere_sweep.h"
#include "bench/long_double.h"
#include "bench/oracle_timing.h"
#include "bench/audit_timing.h"
#include "bench/robust_fallback.h"
#include "bench/timing.h"
#include "cli/app.h"
#include "cli/commands.h"
#include "compare/audit.h"
#include "compare/stability.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "report/audit_pass.h"
#include "report/audit_report.h"
#include "report/audit_timing_report.h"
#include "report/bench_report.h"
#include "report/benchmark_json.h"
#include "report/json_line.h"
#include "report/markdown_report.h"
#include "report/stability_report.h"

namespace rayverify::cli {
namespace {

using json = nlohmann::ordered_json;


struct bench_options {
    std::vector<std::string> corpus;
    std::vector<std::string> variants;
    std::vector<std::string> plugins;
    std::vector<std::string> engines;  // shipped libraries (cli/shipped_libraries.h)
    plugin_isolation isolation;
    std::vector<std::string> families;
    std::vector<std::string> precisions;  // float, double, long_double; empty: all three
    unsigned threads = 0;                 // the accuracy audit's; 0: every hardware thread
    bool oracle = false;
    bool audit = false;
    std::string report_dir;
    std::string benchmark_json;  // Google Benchmark's JSON format
    std::string per_case_file;   // the accuracy audit's per-case lines (float and double targets)
    int repetitions = 9;
    double min_time = 0.01;
    std::size_t sweep = 5000;
    std::uint64_t seed = 2;  // the far-sphere sweep's
    std::vector<std::string> plot_formats;  // png, svg, pdf; empty: png
    std::string error_measure;              // FIGURE:STATISTIC; empty: the plot script's default
};

// The timings' progress line (the harness calls back through a plain function).
terminal::progress* timing_line = nullptr;
void progress(std::size_t done, std::size_t total) {
    if (timing_line == nullptr) return;
    timing_line->set_total(static_cast<double>(total));
    timing_line->update(static_cast<double>(done));
    if (done == total) timing_line->finish();
}

// Shows `line` as the timings' progress while in scope.
struct timing_progress {
    explicit timing_progress(terminal::progress& line) { timing_line = &line; }
    ~timing_progress() { timing_line = nullptr; }
};

// What bench audits and times: float and double as audited, then long double
// on double inputs. Plugins are audited and timed beside every built-in
// variant (or the --variant ones), so the plot places them among the known forms.
struct bench_targets {
    std::vector<audit_target> all;
    std::vector<std::string> labels;  // aligned with all
    std::size_t audited = 0;          // all[0, audited): float and double; the rest long double
    std::vector<audit_target> plugins, programs;
};

bench_targets choose_targets(const bench_options& options, const std::vector<corpus_case>& cases,
                             const std::vector<std::string>& judged_precisions, bool with_long_double) {
    bench_targets chosen;
    std::vector<audit_target>& targets = chosen.all;
    targets =
        judged_precisions.empty() ? std::vector<audit_target>{} : select_targets(options.variants, judged_precisions);
    chosen.plugins =
        (options.plugins.empty() && options.engines.empty()) || judged_precisions.empty()
            ? std::vector<audit_target>{}
            : select_targets({}, options.plugins, judged_precisions, options.isolation, options.engines);
    targets.insert(targets.end(), chosen.plugins.begin(), chosen.plugins.end());
    // An engine's library run as a program is audited beside the others but
    // not timed: bench times functions called in this process.
    results_options programs;
    programs.engines = options.engines;
    chosen.programs =
        judged_precisions.empty() ? std::vector<audit_target>{}
                                  : outside_targets(programs, judged_precisions, [&](const case_sink& add) {
                                        for (const corpus_case& c : cases) add(c);
                                        return fingerprint_of(cases);
                                    });
    targets.insert(targets.end(), chosen.programs.begin(), chosen.programs.end());
    for (const audit_target& t : targets) chosen.labels.push_back(t.label());
    chosen.audited = targets.size();
    for (const variant& v : with_long_double ? bench::long_double_variants() : std::vector<variant>{}) {
        if (!options.variants.empty() &&
            std::find(options.variants.begin(), options.variants.end(), v.name) == options.variants.end())
            continue;
        targets.push_back({v, precision::binary64});
        chosen.labels.push_back(v.name + "/long double");
    }
    return chosen;
}

bench::timing_options timing_of(const bench_options& options, const std::vector<audit_target>& plugins,
                                const std::vector<std::string>& timed_precisions) {
    bench::timing_options timing;
    timing.variants = options.variants;
    for (const audit_target& t : plugins)
        if (timing.plugins.empty() || timing.plugins.back().name != t.subject.name) timing.plugins.push_back(t.subject);
    timing.repetitions = options.repetitions;
    timing.min_time_s = options.min_time;
    timing.precisions = timed_precisions;
    return timing;
}

// Run time, per family; the ratios' reference, naive/double, timed in the
// same run whatever --precision leaves out.
std::vector<bench::timing_row> time_targets(const std::map<std::string, std::vector<corpus_case>>& by_family,
                                            const bench::timing_options& timing, bool double_timed) {
    terminal::progress line("bench", "timings");
    const timing_progress shown(line);
    std::vector<bench::timing_row> rows = bench::time_variants(by_family, timing, progress);
    if (!double_timed) {
        bench::timing_options reference = timing;
        reference.variants = {"naive"};
        reference.plugins.clear();
        reference.precisions = {"double"};
        reference.include_oracle = false;
        const std::vector<bench::timing_row> extra = bench::time_variants(by_family, reference, progress);
        rows.insert(rows.end(), extra.begin(), extra.end());
    }
    // robust_sphere.h's segment query, where its ray queries are timed: it has
    // no registry variant (no built-in target casts segments), so bench times
    // it on the target families' rays as segments, with its naive reference.
    if (std::any_of(std::begin(bench::robust_variant_names), std::end(bench::robust_variant_names),
                    [&](const char* name) { return bench::times_builtin(timing, name); })) {
        const std::vector<bench::timing_row> segments = bench::time_segment_queries(by_family, timing);
        rows.insert(rows.end(), segments.begin(), segments.end());
    }
    line.finish();
    return rows;
}

// What the timing table's rows are: the engine ports timed here, with how
// they were compiled; libraries as shipped; programs audited and not timed.
std::string target_notes(const json& timing_section, const bench_targets& targets) {
    std::string text;
    std::vector<std::string> ports_timed;
    for (const json& r : timing_section["overall"]) {
        const std::string name = r["variant"].get<std::string>();
        const variant* v = find_builtin_variant(name);
        if (v != nullptr && !v->build.empty() &&
            std::find(ports_timed.begin(), ports_timed.end(), name) == ports_timed.end())
            ports_timed.push_back(name);
    }
    if (!ports_timed.empty())
        text += fmt::format("engine ports ({}): timed as rayverify compiles them (the build below) and called through their "
                   "function; tools/port_build_benchmark.sh times them as their engines' Release builds compile "
                   "the same code (-O3, vectoriser on; docs/bench.md)\n",
                   fmt::join(ports_timed, ", "));
    for (const audit_target& t : targets.plugins)
        if (t.subject.library)
            text += fmt::format("{}: {} {} as shipped ({}): its time includes the library's own call overhead (see "
                       "docs/engines.md)\n",
                       t.label(), t.subject.library->name, t.subject.library->version, t.subject.library->source);
    for (const audit_target& t : targets.programs)
        text += fmt::format("{}: {} {} ({}) audited, not timed: it runs as a node program answering through a pipe\n",
                   t.label(), t.subject.library->name, t.subject.library->version, t.subject.library->source);
    return text;
}

// The corpus files read and the plugins given, each by path, size and digest.
json input_files_json(const corpus_reading& reading, const std::vector<std::string>& plugins) {
    json files = json::array();
    const auto add = [&](const std::filesystem::path& path, const char* role, const std::string& option) {
        std::error_code error;
        const auto bytes = std::filesystem::file_size(path, error);
        files.push_back({{"role", role},
                         {"path", path.string()},
                         {"bytes", error ? json() : json(bytes)},
                         {"digest", files_digest({path}, option)}});
    };
    for (const corpus_reading::argument_tally& a : reading.arguments)
        for (const std::filesystem::path& file : a.argument.files) add(file, "corpus", "--corpus");
    for (const std::string& plugin : plugins) add(plugin, "plugin", "--plugin");
    return files;
}

// bench --oracle: the exact oracles' cost per case against the naive double
// intersector, per family, with the filter's fallback rates and the oracle's cost targets.
int run_oracle_timing(const std::vector<corpus_case>& cases, const bench_options& options) {
    bench::oracle_timing_options timing;
    timing.repetitions = options.repetitions;
    timing.min_time_s = std::max(options.min_time, 0.05);
    terminal::progress line("bench", "timings");
    const timing_progress shown(line);
    const bench::oracle_timing t = bench::time_oracle(cases, timing, progress);
    line.finish();
    fmt::print("{}", bench::format_oracle_timing(t));
    fmt::print("build: {}; CPU: {}\n", build_summary(), bench::cpu_model());
    return exit_ok;
}

// The options that cannot go together, refused before the corpus is read.
void check_bench_options(const bench_options& options) {
    // Its timings and choices are of the code as compiled, in the IEEE default.
    if (!options.isolation.environment.empty())
        throw input_error("", 0, "--fp-env",
                          "bench times and judges its targets in the IEEE default; --fp-env is for audit, gate, "
                          "explain, hunt and render");
    if (options.oracle && !options.benchmark_json.empty())
        throw input_error("", 0, "--benchmark-json", "times the variants: not with --oracle");
    if (options.oracle && !options.precisions.empty())
        throw input_error("", 0, "--precision", "times the variants: not with --oracle (the oracle is exact)");
    if ((options.oracle || options.audit) && !options.per_case_file.empty())
        throw input_error("", 0, "--per-case", "writes the accuracy audit's lines: not with --oracle or --audit");
    if ((!options.plot_formats.empty() || !options.error_measure.empty()) && options.report_dir.empty())
        throw input_error("", 0, options.plot_formats.empty() ? "--error-measure" : "--plot-format",
                          "chooses how the report's plots are drawn: add --report DIR");
    if (options.audit && (!options.benchmark_json.empty() || !options.precisions.empty() || !options.report_dir.empty()))
        throw input_error("", 0, "--audit",
                          fmt::format("times the audit of the {} textbook variants: not with --benchmark-json, "
                                      "--precision or --report",
                                      textbook_variant_names().size()));
}

// The corpus's cases of the chosen families (all by default), and what was read.
std::vector<corpus_case> read_bench_cases(const bench_options& options, const std::vector<std::filesystem::path>& paths,
                                          corpus_reading& reading) {
    std::vector<corpus_case> cases;
    for (corpus_case& c : read_corpus(paths, &reading))
        if (options.families.empty() ||
            std::find(options.families.begin(), options.families.end(), c.family) != options.families.end())
            cases.push_back(std::move(c));
    terminal::note("bench: read " + reading.text());
    if (cases.empty()) throw input_error("", 0, "--family", "no case of the chosen families in the corpus");
    return cases;
}

// bench --audit: the whole audit's cost per case-target, per family, with its stages.
int run_audit_timing(const std::vector<corpus_case>& cases, const bench_options& options) {
    const auto whole_pass = [](const case_source& next, const std::vector<audit_target>& targets,
                               std::ostream* per_case) { return run_audit_pass(next, targets, 1, true, per_case).audit.cases; };
    fmt::print("{}", audit_timing_text(bench::measure_audit_timing(cases, options.repetitions,
                                                                   std::max(options.min_time, 0.05), whole_pass)));
    return exit_ok;
}

// --precision: the precisions audited (float, double) and timed (the same,
// and "long double", the name timing rows carry for long_double).
struct precision_choice {
    std::vector<std::string> judged, timed;
    bool long_double = false;
    bool double_timed = false;  // else naive/double, the ratios' reference, is timed on its own
};
precision_choice precisions_of(const bench_options& options) {
    const auto chosen = [&](const std::string& name) {
        return options.precisions.empty() ||
               std::find(options.precisions.begin(), options.precisions.end(), name) != options.precisions.end();
    };
    precision_choice choice;
    for (const std::string& p : precision_names())
        if (chosen(p)) {
            choice.judged.emplace_back(p);
            choice.timed.emplace_back(p);
        }
    choice.long_double = chosen("long_double");
    if (choice.long_double) choice.timed.emplace_back("long double");
    choice.double_timed = chosen("double");
    return choice;
}

int run(const bench_options& options, const std::string& command_line) {
    check_bench_options(options);
    const plot_choices plots_chosen = plot_choices_of(options.plot_formats, options.error_measure);
    std::vector<std::filesystem::path> paths(options.corpus.begin(), options.corpus.end());
    if (paths.empty()) paths.emplace_back(default_corpus());
    corpus_reading reading;
    const std::vector<corpus_case> cases = read_bench_cases(options, paths, reading);
    if (options.oracle) return run_oracle_timing(cases, options);
    if (options.audit) return run_audit_timing(cases, options);
    const precision_choice precisions = precisions_of(options);
    // The outputs, declared before the work; committed after it.
    run_outputs outputs;
    declare_inputs(outputs, paths, options.corpus.empty() ? "the default corpus" : "--corpus");
    declare_inputs(outputs, {options.plugins.begin(), options.plugins.end()}, "--plugin");
    std::optional<report_bundle> bundle;
    if (!options.report_dir.empty()) bundle.emplace(outputs, options.report_dir, "--report");
    output_file* table_csv =
        bundle ? &outputs.file(bundle->dir() / "bench.csv", "--report") : nullptr;  // report.json's figures as a table
    output_file* per_case_file =
        options.per_case_file.empty() ? nullptr : &outputs.file(options.per_case_file, "--per-case");
    output_file* benchmark_file =
        options.benchmark_json.empty() ? nullptr : &outputs.file(options.benchmark_json, "--benchmark-json");

    const bench_targets chosen_targets = choose_targets(options, cases, precisions.judged, precisions.long_double);
    const std::vector<audit_target>& targets = chosen_targets.all;
    const std::vector<std::string>& labels = chosen_targets.labels;
    const std::size_t audited = chosen_targets.audited;
    bench_accuracy accuracy;
    accuracy.audited = audited;
    for (const std::string& l : labels) accuracy.precision_labels.push_back(l.substr(l.find('/') + 1));
    if (isatty(STDERR_FILENO)) terminal::note(fmt::format("bench: auditing {} cases", cases.size()));
    const unsigned threads = audit_threads(targets, thread_count(options.threads));
    accuracy.run = audit_with_stability(cases, targets, labels, threads,
                                        per_case_file ? &per_case_file->stream() : nullptr, audited);

    // Run time, per family, on the machine as recorded when the timings begin.
    bench_provenance provenance;
    provenance.machine = bench::read_machine_record();
    provenance.input_files = input_files_json(reading, options.plugins);
    std::map<std::string, std::vector<corpus_case>> by_family;
    for (const corpus_case& c : cases) by_family[family_key(c)].push_back(c);
    const bench::timing_options timing = timing_of(options, chosen_targets.plugins, precisions.timed);
    const std::vector<bench::timing_row> rows = time_targets(by_family, timing, precisions.double_timed);
    const json timing_section = timing_json(rows, timing, bench_reference_label);
    if (benchmark_file != nullptr)
        benchmark_file->stream() << json_text(benchmark_json(rows, current_benchmark_context(command_line)), 2) << '\n';

    fmt::print("{}", timing_table_text(timing_section, cases.size(), options.repetitions));
    fmt::print("{}", target_notes(timing_section, chosen_targets));
    const robust_sphere_figures robust = robust_figures(rows, by_family);
    fmt::print("{}", robust.text);
    fmt::print("build: {}; CPU: {}\n", build_summary(), bench::cpu_model());
    if (bundle) {
        // The report: the audit's sections for float and double, then ours.
        run_context context{command_line, {}, {}};
        for (const auto& p : paths) context.corpus_paths.push_back(p.string());
        std::optional<far_sphere_sweep_run> sweep;
        if (options.sweep > 0) {
            const std::vector<corpus_case> sweep_cases = bench::far_sphere_sweep(options.sweep, options.seed);
            const std::vector<audit_target> sweep_targets(targets.begin(), targets.begin() + static_cast<long>(audited));
            const std::vector<std::string> sweep_labels(labels.begin(), labels.begin() + static_cast<long>(audited));
            sweep = far_sphere_sweep_run{sweep_cases.size(), options.seed,
                                         audit_with_stability(sweep_cases, sweep_targets, sweep_labels, threads)};
        }
        json report = bench_report_document(accuracy, context, timing_section, robust.json, sweep, provenance);
        table_csv->stream() << bench_table_csv(report);
        const plot_outcome plots = bundle->write(std::move(report), true, plots_chosen);
        fmt::print("report: {}\nplots: {}\n", (bundle->dir() / "report.json").string(), plots.message);
    }
    check_standard_output();
    outputs.commit();
    return exit_ok;
}

}  // namespace

command add_bench_command(CLI::App& app, const std::string& command_line) {
    auto options = std::make_shared<bench_options>();
    auto* sub = app.add_subcommand("bench", "Time every variant in float, double and long double on each corpus "
                                            "family (Google Benchmark), beside its accuracy and stability, and the "
                                            "exact oracle's cost; --report writes report.json, report.md and plots.");
    sub->add_option("--corpus", options->corpus, "Corpus file or directory; repeatable. Default: the shipped corpus");
    sub->add_option("--variant", options->variants, "Variant to time (repeatable; default: all built-in)");
    sub->add_option("--plugin", options->plugins,
                    "Shared library implementing rayverify_plugin.h, audited and timed beside the built-in variants "
                    "(timed through its entry point in a loop of its own, its guards checked once per pass; "
                    "repeatable)");
    sub->add_option("--engine", options->engines,
                    "An engine's library as its package installs it (`rayverify engines`), audited and, when called "
                    "through a plugin, timed beside the built-in variants, its own call overhead included "
                    "(repeatable)");
    add_isolation_options(sub, options->isolation);
    sub->add_flag("--oracle", options->oracle,
                  "Time the exact oracles instead: the filtered oracle and the reference route against the naive "
                  "double intersector per family, with the filter's fallback rates");
    sub->add_flag("--audit", options->audit,
                  fmt::format("Time the whole audit instead (the {} textbook variants in float and double, one "
                              "thread) per case-target against the naive double intersector per family, with the "
                              "share of figures each stage of the oracle settled",
                              textbook_variant_names().size()))
        ->excludes("--oracle");
    sub->add_option("--family", options->families, "Only cases of this family (repeatable; default: all)");
    sub->add_option("--precision", options->precisions,
                    "float, double or long_double (repeatable; default: all three). naive/double, the ratios' "
                    "reference, is timed in every run")
        ->check(CLI::IsMember([] {
            std::vector<std::string> names = precision_names();
            names.emplace_back("long_double");
            return names;
        }()));
    sub->add_option("--threads", options->threads,
                    "Threads of the accuracy audit (default: every hardware thread; the figures are the same for "
                    "any number). The timings always run on one thread")
        ->check(whole_number(1, 4096));
    sub->add_option("--report", options->report_dir, "Directory for report.json, report.md and the PNG plots");
    sub->add_option("--per-case", options->per_case_file,
                    "Write the accuracy audit's per-case JSON lines (as audit --per-case: every float and double "
                    "target; long double is summarised, not lined) to this file");
    sub->add_option("--benchmark-json", options->benchmark_json,
                    "Also write the timings in Google Benchmark's JSON format (mean, median, stddev, cv per "
                    "benchmark; readable by its compare.py)");
    sub->add_option("--repetitions", options->repetitions, "Timed repetitions per benchmark (default 9)")
        ->check(whole_number(1, 1000));
    sub->add_option("--min-time", options->min_time, "Minimum seconds per repetition (default 0.01)")
        ->check(finite_number(0, 3600, true));
    sub->add_option("--sweep", options->sweep, "Far-sphere sweep cases for the report (default 5000; 0: none)")
        ->check(whole_number(0, 100000000));
    sub->add_option("--plot-format", options->plot_formats,
                    "With --report: draw each plot as png, svg or pdf (repeatable; default png)");
    sub->add_option("--error-measure", options->error_measure,
                    "With --report: the error the accuracy-against-time plot draws, FIGURE:STATISTIC: an error "
                    "figure of report.json and max, p99 or median (default near_root_scaled_ulp:max: a root "
                    "exactly at 0 counted in ulps of r/|d|, so that it cannot blow up the figure)");
    sub->add_option("--seed", options->seed,
                    "Seed of the far-sphere sweep's cases, as `corpus generate --family far_sphere --seed` takes it; "
                    "the report and far_sphere.png name it (default 2)")
        ->check(whole_number(0));
    return {sub, [options, command_line] { return run(*options, command_line); }};
}

}  // namespace rayverify::cli
