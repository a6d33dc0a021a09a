#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <thread>

#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "corpus/shard_environment.h"
#include "report/atomic_file.h"
#include "report/audit_report.h"
#include "report/audit_summary.h"
#include "report/markdown_report.h"
#include "report/shard_state.h"
#include "report/stability_report.h"

namespace rayverify::cli {
namespace {

struct audit_options {
    std::vector<std::string> corpus;
    std::vector<std::string> generate;
    std::vector<std::string> variants;
    std::vector<std::string> plugins;
    plugin_isolation isolation;
    std::vector<std::string> precisions;
    std::string report_dir;
    std::string per_case_file;
    bool plots = false;
    audit_presentation presentation;
    unsigned threads = 0;  // 0: every hardware thread
    std::string shard;
    std::string scene;  // issue 6: audit a scene's rays instead (cli/scene_audit.cpp)
};

// Progress on stderr, only when a person is watching it.
std::function<void(std::size_t)> progress_reporter() {
    if (!isatty(STDERR_FILENO)) return {};
    return [](std::size_t done) { fmt::print(stderr, "\raudit: {} cases", done); };
}

// Where a shard's per-case file is, as the merge finds it: relative to the
// report directory when inside it (so shard directories can be moved, e.g.
// as CI artifacts), else absolute.
std::string per_case_location(const std::filesystem::path& per_case, const std::filesystem::path& report_dir) {
    std::error_code error;
    const auto file = std::filesystem::weakly_canonical(std::filesystem::absolute(per_case), error);
    const auto dir = std::filesystem::weakly_canonical(std::filesystem::absolute(report_dir), error);
    const auto relative = file.lexically_relative(dir);
    if (!relative.empty() && *relative.begin() != "..") return relative.generic_string();
    return file.string();
}

int run(const audit_options& options, const std::string& command_line) {
    if (!options.scene.empty()) {
        if (!options.corpus.empty() || !options.generate.empty() || !options.shard.empty() ||
            !options.per_case_file.empty() || options.plots)
            throw input_error("", 0, "--scene",
                              "a scene makes its own rays: no --corpus, --generate, --shard, --per-case or --plots");
        return run_scene_audit({options.scene, options.variants, options.plugins, options.precisions,
                                options.isolation, options.report_dir, command_line});
    }
    if (!options.corpus.empty() && !options.generate.empty())
        throw input_error("", 0, "--generate", "give either --corpus or --generate, not both");
    const shard_spec shard = options.shard.empty() ? shard_spec{} : chosen_shard(options.shard, "audit");
    if (!options.shard.empty() && options.report_dir.empty())
        throw input_error("", 0, "--shard", "a shard needs --report DIR (its state for `rayverify merge` goes there)");
    std::vector<std::filesystem::path> paths(options.corpus.begin(), options.corpus.end());
    std::vector<generate_spec> specs;
    for (const std::string& text : options.generate) specs.push_back(parse_generate_spec(text));
    if (paths.empty() && specs.empty()) paths.emplace_back(default_corpus());
    case_stream stream = specs.empty() ? case_stream(paths, shard) : case_stream(specs, shard);
    const std::vector<audit_target> targets =
        select_targets(options.variants, options.plugins, options.precisions, options.isolation);
    if (targets.empty()) throw input_error("", 0, "--precision", "no variant runs in the chosen precision");
    const unsigned requested = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    const unsigned threads = audit_threads(targets, requested);
    if (threads < requested)
        fmt::print(stderr, "audit: a plugin is not thread-safe (called from one thread): auditing on one thread\n");

    // Every output is opened (as a temporary) before the audit and committed
    // only once all of them are complete: an error leaves no output behind.
    const std::filesystem::path report_dir(options.report_dir);
    refuse_directory(options.per_case_file, "--per-case");
    audit_outputs outputs;
    outputs.open_report(report_dir);  // first: it creates the directory, which may hold the per-case file
    if (!options.per_case_file.empty()) outputs.per_case.emplace(options.per_case_file);
    open_presentation(outputs, options.presentation);
    std::optional<atomic_file> state_file;
    if (!options.shard.empty()) {
        refuse_directory(report_dir / shard_state_file, "--report");
        state_file.emplace(report_dir / shard_state_file);
    }

    // Per thread: the state, and the chunk's rendered per-case lines (written in order).
    std::vector<audit_state> states(threads, audit_state(targets));
    std::vector<std::string> lines(outputs.per_case ? case_stream::default_chunk : 0);
    audit_hooks hooks;
    hooks.parallel = [&](const audited_case& c, std::size_t index, std::size_t slot, unsigned worker) {
        const case_stability s = assess_case(c);
        states[worker].stability.add(c, s, index);
        if (outputs.report_json) states[worker].points.add(c, s, index);
        if (!outputs.per_case) return;
        nlohmann::ordered_json line = per_case_json(c, targets);
        add_stability_fields(line, s);
        lines[slot] = line.dump();
    };
    if (outputs.per_case)
        hooks.ordered = [&](const audited_case&, std::size_t, std::size_t slot) {
            outputs.per_case->stream() << lines[slot] << '\n';
        };
    hooks.progress = progress_reporter();
    const case_source next = [&](std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
        return stream.next(cases, indices);
    };
    states[0].audit = audit_stream(next, targets, threads, hooks);
    if (hooks.progress) fmt::print(stderr, "\n");
    for (unsigned w = 1; w < threads; ++w) {
        states[0].stability.merge(states[w].stability);
        states[0].points.merge(states[w].points);
    }

    run_context context{recorded_command(command_line), {}, {}};
    for (const auto& p : paths) context.corpus_paths.push_back(p.string());
    for (const generate_spec& s : specs) context.generated.push_back(s.text());
    std::optional<nlohmann::ordered_json> report;
    if (outputs.report_json || outputs.summary_md) {
        report = audit_report_document(states[0], context);
        if (state_file) {
            nlohmann::ordered_json state = {
                {"format", shard_state_format},
                {"build", build_json()},
                {"command", context.command_line},
                {"input", {{"paths", context.corpus_paths},
                           {"generated", context.generated},
                           {"cases", stream.total()},
                           {"fingerprint", stream.fingerprint()}}},
                {"shard", {{"index", shard.index}, {"count", shard.count}, {"cases", states[0].audit.cases}}},
                {"targets", targets_json(targets)},
                {"per_case_file", options.per_case_file.empty()
                                      ? nlohmann::ordered_json(nullptr)
                                      : nlohmann::ordered_json(per_case_location(options.per_case_file, report_dir))},
                {"state", state_json(states[0])}};
            state_file->stream() << state.dump() << '\n';
            (*report)["shard"] = {{"index", shard.index},
                                  {"count", shard.count},
                                  {"cases", states[0].audit.cases},
                                  {"input_cases", stream.total()},
                                  {"merge", "rayverify merge -o DIR SHARD_DIR... combines the shards' " +
                                                std::string(shard_state_file) + " into the whole run's report"}};
        }
    }
    if (state_file) state_file->commit();
    return publish_audit(states[0].audit.finish(), report, report_dir, outputs, options.plots, options.presentation);
}

}  // namespace

shard_spec chosen_shard(const std::string& text, const char* command) {
    const resolved_shard resolved = resolve_shard(text, process_environment());
    if (text.starts_with("auto")) fmt::print(stderr, "{}: {}\n", command, resolved.origin);
    return resolved.shard;
}

std::string recorded_command(const std::string& command_line) {
    // Options that choose where the outputs go or how the work is spread or
    // run change no figure: they are left out, so that any thread count, any
    // sharding, any output file or directory and a plugin isolated or not
    // record the same command.
    static const std::vector<std::string> with_value = {"--threads",        "--shard",      "--report", "--per-case",
                                                        "--summary-md",     "--plugin-timeout", "-o",   "--output"};
    static const std::vector<std::string> flags = {"--plots", "--isolate", "--summary"};
    const std::vector<std::string> words = command_words(command_line);
    std::string out;
    for (std::size_t i = 0; i < words.size(); ++i) {
        const std::string& w = words[i];
        const auto named = [&](const std::string& option) { return w == option || w.starts_with(option + "="); };
        if (std::any_of(with_value.begin(), with_value.end(), named)) {
            if (w.find('=') == std::string::npos) ++i;  // and its value
            continue;
        }
        if (std::find(flags.begin(), flags.end(), w) != flags.end()) continue;
        out += (out.empty() ? "" : " ") + w;
    }
    return out;
}

void audit_outputs::created_directory::create(const std::filesystem::path& dir) {
    std::error_code error;
    const bool existed = std::filesystem::exists(dir, error);
    std::filesystem::create_directories(dir, error);
    if (error) throw input_error(dir.string(), 0, "--report", "cannot create directory: " + error.message());
    if (!existed) path = dir;
}

audit_outputs::created_directory::~created_directory() {
    if (path.empty() || keep) return;
    std::error_code ignored;
    std::filesystem::remove(path, ignored);  // removes only an empty directory
}

void audit_outputs::open_report(const std::filesystem::path& report_dir) {
    if (report_dir.empty()) return;
    dir = report_dir;
    refuse_directory(report_dir / "report.json", "--report");
    refuse_directory(report_dir / "summary.txt", "--report");
    created.create(report_dir);
    report_json.emplace(report_dir / "report.json");
    summary.emplace(report_dir / "summary.txt");
}

int publish_audit(const audit_totals& totals, const std::optional<nlohmann::ordered_json>& report,
                  const std::filesystem::path& report_dir, audit_outputs& outputs, bool plots,
                  const audit_presentation& presentation) {
    const std::string table = render_summary_table(totals);
    if (outputs.report_json) {
        outputs.report_json->stream() << report->dump(2) << '\n';
        outputs.summary->stream() << table;
    }
    if (outputs.summary_md) outputs.summary_md->stream() << render_summary_markdown(*report);
    for (std::optional<atomic_file>* output :
         {&outputs.per_case, &outputs.report_json, &outputs.summary, &outputs.summary_md})
        if (*output) (*output)->commit();
    outputs.created.keep = true;

    fmt::print("{}", presentation.summary ? render_family_summary(totals) : table);
    fmt::print("build: {}\n", build_summary());
    if (outputs.report_json) {
        // report.md and the plots render the committed report.json.
        const plot_outcome drawn = write_report_bundle(report_dir, *report, plots);
        fmt::print("report: {}\n", (report_dir / "report.json").string());
        fmt::print("plots: {}\n", drawn.message);
    }
    bool findings = false;
    for (const target_tally& t : totals.overall) findings = findings || t.disagreements() > 0;
    return findings ? exit_findings : exit_ok;
}

command add_audit_command(CLI::App& app, const std::string& command_line) {
    auto options = std::make_shared<audit_options>();
    auto* sub = app.add_subcommand("audit", "Run intersectors beside the exact oracle over a corpus and report "
                                            "every disagreement and error statistic. Exit 1 when any variant "
                                            "disagrees with the exact answer on some case.");
    sub->add_option("--corpus", options->corpus,
                    "Corpus file (.txt or .csv) or directory of them; repeatable. Default: the shipped corpus");
    sub->add_option("--generate", options->generate,
                    "Audit generated cases instead of a corpus, made on the fly (no file, bounded memory): "
                    "FAMILY:COUNT[:SEED], seed 1 by default, families as `corpus generate`; repeatable");
    sub->add_option("--scene", options->scene,
                    "Audit exactly the rays a scene file casts (corpus/scenes/README.md), judged at the level each "
                    "ray's query needs, instead of a corpus");
    sub->add_option("--variant", options->variants, "Variant to audit (repeatable; default: all)");
    sub->add_option("--plugin", options->plugins,
                    "Shared library implementing rayverify_plugin.h, audited as a variant (repeatable)");
    add_isolation_options(sub, options->isolation);
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember({"float", "double"}));
    sub->add_option("--report", options->report_dir,
                    "Directory for report.json, summary.txt, report.md and the PNG plots");
    sub->add_flag("--plots", options->plots,
                  "With --report: also draw the PNG plots (tools/plot_report.py, matplotlib; takes seconds)");
    add_presentation_options(sub, options->presentation);
    sub->add_option("--per-case", options->per_case_file, "Write one JSON object per case to this file");
    sub->add_option("--threads", options->threads,
                    "Threads auditing cases (default: every hardware thread); the output is the same for any number")
        ->check(CLI::Range(1u, 4096u));
    sub->add_option("--shard", options->shard,
                    "Audit only shard K of N (K = 1..N): the cases whose index in the whole input is K-1 modulo N. "
                    "`auto` reads K and N from a Slurm job array, `auto/N` also from a Kubernetes Indexed Job, or "
                    "RAYVERIFY_SHARD_INDEX (0-based) and RAYVERIFY_TOTAL_SHARDS (docs/scaling_out.md). Needs "
                    "--report DIR, where the shard's state goes; `rayverify merge` combines the N shards into the "
                    "report of the whole run");
    return {sub, [options, command_line] { return run(*options, command_line); }};
}

}  // namespace rayverify::cli
