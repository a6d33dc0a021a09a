#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>

#include "cli/app.h"
#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "corpus/shard_environment.h"
#include "report/audit_pass.h"
#include "report/audit_report.h"
#include "report/audit_summary.h"
#include "report/case_list.h"
#include "report/contract_hints.h"
#include "report/json_line.h"
#include "report/markdown_report.h"
#include "report/schema.h"
#include "report/shard_state.h"
#include "report/stability_report.h"
#include "report/table_csv.h"

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
    std::string failures_file;
    bool plots = false;
    audit_presentation presentation;
    unsigned threads = 0;  // 0: every hardware thread
    std::string shard;
    std::string scene;  // audit a scene's rays instead (cli/scene_audit.cpp)
    std::string oracle_route = std::string(oracle_route_name(rayverify::oracle_route::filtered));
    results_options results;
};

// Where a shard's per-case file is, as the merge finds it: relative to the
// report directory, which must hold it (so shard directories can be moved,
// e.g. as CI artifacts, and merge reads nothing outside them).
std::string per_case_location(const std::filesystem::path& per_case, const std::filesystem::path& report_dir) {
    std::error_code error;
    const auto file = std::filesystem::weakly_canonical(std::filesystem::absolute(per_case), error);
    const auto dir = std::filesystem::weakly_canonical(std::filesystem::absolute(report_dir), error);
    const auto relative = file.lexically_relative(dir);
    if (relative.empty() || *relative.begin() == ".." || relative.is_absolute())
        throw input_error(per_case.string(), 0, "--per-case",
                          "with --shard, the per-case file goes inside the --report directory (" +
                              report_dir.string() + "), which `rayverify merge` reads");
    return relative.generic_string();
}

// A stream that passes everything to `out` and digests it on the way.
class digesting_buffer : public std::streambuf {
public:
    explicit digesting_buffer(std::ostream& out) : out_(out) {}
    const fnv1a_digest& digest() const { return digest_; }

protected:
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        const char byte = traits_type::to_char_type(c);
        xsputn(&byte, 1);
        return c;
    }
    std::streamsize xsputn(const char* data, std::streamsize n) override {
        digest_.add(std::string_view(data, static_cast<std::size_t>(n)));
        out_.write(data, n);
        return n;
    }

private:
    std::ostream& out_;
    fnv1a_digest digest_;
};

// What decides a shard's result besides its cases (whose fingerprint the
// state records): the answers of a results file (with an npy's companion),
// the plugin libraries. `merge` requires the same digests of every shard,
// however the paths were spelled.
shard_header::digests_record input_digests(const audit_options& options) {
    shard_header::digests_record digests;
    if (!options.results.file.empty()) {
        std::vector<std::filesystem::path> files{options.results.file};
        if (exchange_format_of(options.results.file) == exchange_format::npy)
            files.push_back(sidecar_of(options.results.file));
        digests.results = files_digest(files, "--results");
    }
    for (const std::string& p : options.plugins) digests.plugins.push_back(files_digest({p}, "--plugin"));
    return digests;
}

// The options that cannot go together, refused before anything is read.
void check_audit_options(const audit_options& options) {
    if (options.plots && options.report_dir.empty())
        throw input_error("", 0, "--plots", "the plots are drawn into the report directory: add --report DIR");
    if (!options.shard.empty() && options.report_dir.empty())
        throw input_error("", 0, "--shard", "a shard needs --report DIR (its state for `rayverify merge` goes there)");
}

// The targets judged: the variants and plugins chosen, then what answers
// from outside (a results file answers the whole input, every shard's cases,
// checked before any case is judged; a program or an engine's node is asked
// each chunk's cases as they are judged).
std::vector<audit_target> audit_targets(const audit_options& options, const case_input& input) {
    const std::vector<audit_target> outside = outside_targets(
        options.results, options.precisions,
        [&](const case_sink& add) {
            case_stream whole = input.open();
            std::vector<corpus_case> cases;
            std::vector<std::size_t> indices;
            while (whole.next(cases, indices)) {
                for (const corpus_case& c : cases) add(c);
                cases.clear();
                indices.clear();
            }
            return whole.fingerprint();
        },
        std::nullopt, programs_answer::chunk_by_chunk);
    std::vector<audit_target> targets = targets_with_results(options.variants, options.plugins, options.precisions,
                                                             options.isolation, options.results, outside);
    if (targets.empty()) throw input_error("", 0, "--precision", "no variant runs in the chosen precision");
    return targets;
}

// The threads the audit runs on: those asked for (`requested`), or one
// where a target must be called from one thread, said so.
unsigned audit_thread_count(const audit_options& options, const std::vector<audit_target>& targets,
                            unsigned requested) {
    const unsigned threads = audit_threads(targets, requested);
    if (threads < requested)
        terminal::note(options.isolation.child_process
                           ? "audit: --isolate answers each plugin's calls in one child process, one at a time: "
                             "auditing on one thread"
                           : "audit: a plugin is not thread-safe (called from one thread): auditing on one thread");
    return threads;
}

// A shard's state for `rayverify merge` (its header: the build, the input and
// its digests, the shard, the targets, the per-case file and its digest), and
// the report's note of the shard.
void write_shard_state(output_file& state_file, const audit_options& options, const run_context& context,
                       const case_stream& stream, const shard_spec& shard, const std::vector<audit_target>& targets,
                       const audit_state& audited, const std::string& per_case_location_in_shard,
                       const digesting_buffer* per_case_digest, nlohmann::ordered_json& report) {
    shard_header header;
    header.schema_version = schema_version::shard_state;
    header.format = shard_state_format;
    header.build = build_json();
    header.command = context.command_line;
    header.input = {context.corpus_paths, context.generated, stream.total(), stream.fingerprint(),
                    input_digests(options)};
    header.shard = shard;
    header.cases = audited.audit.cases;
    header.targets = targets;
    if (!per_case_location_in_shard.empty()) {
        header.per_case_file = per_case_location_in_shard;
        header.per_case_digest = per_case_digest->digest().text();
    }
    state_file.stream() << json_text(shard_document(header, audited)) << '\n';
    report["shard"] = {{"index", shard.index},
                       {"count", shard.count},
                       {"cases", audited.audit.cases},
                       {"input_cases", stream.total()},
                       {"merge", "rayverify merge --report DIR SHARD_DIR... combines the shards' " +
                                     std::string(shard_state_file) + " into the whole run's report"}};
}

int run(const audit_options& options, const std::string& command_line) {
    const oracle_route route = *oracle_route_from_name(options.oracle_route);  // checked by the option
    if (!options.scene.empty()) {
        if (!options.corpus.empty() || !options.generate.empty() || !options.shard.empty() ||
            !options.per_case_file.empty() || options.plots)
            throw input_error("", 0, "--scene",
                              "a scene makes its own rays: no --corpus, --generate, --shard, --per-case or --plots");
        return run_scene_audit({options.scene, options.variants, options.plugins, options.precisions,
                                options.isolation, options.report_dir, command_line, options.results, route});
    }
    check_audit_options(options);
    const shard_spec shard = options.shard.empty() ? shard_spec{} : chosen_shard(options.shard, "audit");
    const case_input input = select_input(options.corpus, options.generate);
    const std::vector<std::filesystem::path>& paths = input.paths;
    const std::vector<generate_spec>& specs = input.specs;
    const std::string per_case_location_in_shard =
        options.shard.empty() || options.per_case_file.empty()
            ? std::string()
            : per_case_location(options.per_case_file, options.report_dir);
    case_stream stream = input.open(shard);
    const std::vector<audit_target> targets = audit_targets(options, input);
    const unsigned requested = thread_count(options.threads);
    const unsigned threads = audit_thread_count(options, targets, requested);

    // Every output is declared (opened as a temporary) before the audit and
    // committed only once all of them are complete: an error leaves no output behind.
    const std::filesystem::path report_dir(options.report_dir);
    audit_outputs outputs;
    declare_inputs(outputs.files, paths, options.corpus.empty() && specs.empty() ? "the default corpus" : "--corpus");
    declare_inputs(outputs.files, {options.plugins.begin(), options.plugins.end()}, "--plugin");
    declare_results_inputs(outputs.files, options.results);
    outputs.open_report(report_dir, "--report");  // first: it creates the directory, which may hold the per-case file
    if (!options.per_case_file.empty()) outputs.per_case = &outputs.files.file(options.per_case_file, "--per-case");
    output_file* failures =
        options.failures_file.empty() ? nullptr : &outputs.files.file(options.failures_file, "--failures");
    if (failures != nullptr)
        failures->stream() << corpus_header_comment() << "\n# every case some target disagrees on: "
                           << recorded_command(command_line) << '\n';
    open_presentation(outputs, options.presentation);
    output_file* state_file =
        options.shard.empty() ? nullptr : &outputs.files.file(report_dir / shard_state_file, "--report");

    // A shard's per-case file is digested as it is written: merge checks it is that very file.
    std::optional<digesting_buffer> per_case_digest;
    std::optional<std::ostream> per_case_stream;
    if (outputs.per_case != nullptr && !per_case_location_in_shard.empty()) {
        per_case_digest.emplace(outputs.per_case->stream());
        per_case_stream.emplace(&*per_case_digest);
        per_case_stream->exceptions(std::ios::badbit);
    }

    audit_progress progress(paths, specs, shard);
    const case_source next = [&](std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
        return stream.next(cases, indices);
    };
    audit_state audited = run_audit_pass(next, targets, threads, static_cast<bool>(outputs.report),
                                       per_case_stream                ? &*per_case_stream
                                       : outputs.per_case != nullptr ? &outputs.per_case->stream()
                                                                     : nullptr,
                                       progress.reporter(), failures != nullptr ? &failures->stream() : nullptr, {},
                                       route);
    progress.finish();
    finish_outside_answers(targets);  // nothing may follow a program's last answer
    if (!stream.reading().arguments.empty()) terminal::note("audit: read " + stream.reading().text());

    run_context context{recorded_command(command_line), {}, {}};
    for (const auto& p : paths) context.corpus_paths.push_back(p.string());
    for (const generate_spec& s : specs) context.generated.push_back(s.text());
    const audit_totals totals = audited.audit.finish(requested);  // pure computation: every thread asked for
    std::optional<nlohmann::ordered_json> report;
    if (outputs.report || outputs.summary_md != nullptr) {
        report = audit_report_document(audited, totals, context, requested);
        if (state_file != nullptr)
            write_shard_state(*state_file, options, context, stream, shard, targets, audited,
                              per_case_location_in_shard, per_case_digest ? &*per_case_digest : nullptr, *report);
    }
    return publish_audit(totals, std::move(report), outputs, options.plots, options.presentation,
                         render_contract_hints(contract_hints_json(targets, audited.lint.hints())) +
                             render_cases_to_open(cases_to_open_json(targets, audited.examples)));
}

}  // namespace

std::string files_digest(const std::vector<std::filesystem::path>& paths, const std::string& option) {
    fnv1a_digest digest;
    for (const std::filesystem::path& path : paths) {
        if (!add_file_bytes(digest, path)) throw input_error(path.string(), 0, option, "cannot open for reading");
        digest.add("\xff");  // where one file ends
    }
    return digest.text();
}


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
                                                        "--summary-md",     "--plugin-timeout", "-o",   "--output", "--failures"};
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

void audit_outputs::open_report(const std::filesystem::path& dir, const std::string& option) {
    if (dir.empty()) return;
    report.emplace(files, dir, option);
    summary = &files.file(dir / "summary.txt", option);
    table_csv = &files.file(dir / "audit.csv", option);
}

void print_libraries(const std::vector<audit_target>& targets) {
    std::vector<std::string> named;
    for (const audit_target& t : targets) {
        if (!t.subject.library || std::find(named.begin(), named.end(), t.subject.name) != named.end()) continue;
        named.push_back(t.subject.name);
        const library_identity& l = *t.subject.library;
        fmt::print("library: {} is {}{} ({}){}\n", t.subject.name, l.name.empty() ? "a library" : l.name,
                   l.version.empty() ? ", version unknown" : " " + l.version, l.source.empty() ? "source unknown" : l.source,
                   l.configuration.empty() ? "" : ", " + l.configuration);
    }
    std::vector<std::string> environments;
    for (const audit_target& t : targets) {
        if (t.subject.fp_environment.empty() ||
            std::find(environments.begin(), environments.end(), t.subject.name) != environments.end())
            continue;
        environments.push_back(t.subject.name);
        fmt::print("fp environment: {} runs in {}; rayverify's own arithmetic in the IEEE default\n", t.subject.name,
                   t.subject.fp_environment);
    }
}

int publish_audit(const audit_totals& totals, std::optional<nlohmann::ordered_json> report,
                  audit_outputs& outputs, bool plots, const audit_presentation& presentation,
                  const std::string& hints) {
    const std::string table = render_summary_table(totals);
    plot_outcome drawn;
    if (outputs.summary_md != nullptr) outputs.summary_md->stream() << render_summary_markdown(*report);
    if (outputs.report) {
        outputs.summary->stream() << table;
        outputs.table_csv->stream() << audit_table_csv(*report);
        drawn = outputs.report->write(std::move(*report), plots);
    }
    fmt::print("{}", presentation.summary ? render_family_summary(totals) : table);
    fmt::print("{}", hints);
    fmt::print("build: {}\n", build_summary());
    print_libraries(totals.targets);
    if (outputs.report) {
        fmt::print("report: {}\n", (outputs.report->dir() / "report.json").string());
        fmt::print("plots: {}\n", drawn.message);
    }
    // Standard output first: it cannot be taken back, the files can.
    check_standard_output();
    outputs.files.commit();
    bool findings = false;
    for (const target_tally& t : totals.overall) findings = findings || t.disagreements() > 0;
    // A target that judged nothing passed nothing: a finding, said.
    for (std::size_t i = 0; i < totals.targets.size(); ++i)
        if (totals.overall[i].scored_nothing()) {
            terminal::note(fmt::format("audit: {} scored no case of {}: each is invalid at its precision or breaks "
                                       "its contract (not scored): a finding, not a pass",
                                       totals.targets[i].label(), totals.overall[i].cases));
            findings = true;
        }
    return findings ? exit_findings : exit_ok;
}

void declare_inputs(run_outputs& outputs, const std::vector<std::filesystem::path>& paths, const std::string& option) {
    for (const std::filesystem::path& path : paths) {
        std::error_code error;
        outputs.input(path, option, std::filesystem::is_directory(path, error));
    }
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
    add_results_options(sub, options->results);
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember(precision_names()));
    sub->add_option("--report", options->report_dir,
                    "Directory for report.json, summary.txt, report.md and the PNG plots");
    sub->add_flag("--plots", options->plots,
                  "With --report: also draw the PNG plots (tools/plot_report.py, matplotlib; takes seconds)");
    add_presentation_options(sub, options->presentation);
    sub->add_option("--per-case", options->per_case_file, "Write one JSON object per case to this file");
    sub->add_option("--failures", options->failures_file,
                    "Write every case some target disagrees on to this file as a corpus (input order), to audit, "
                    "explain or hunt from again");
    sub->add_option("--oracle-route", options->oracle_route,
                    "filtered (the default): the oracle's filters settle what they can and exact arithmetic the "
                    "rest; reference: no filter, each case solved in exact arithmetic and every figure and "
                    "comparison decided exactly without the filters, slower. Both give the same report, bit for "
                    "bit: the reference route shows it on your own cases")
        ->check(CLI::IsMember(oracle_route_names()));
    sub->add_option("--threads", options->threads,
                    "Threads auditing cases (default: every hardware thread); the output is the same for any number")
        ->check(whole_number(1, 4096));
    sub->add_option("--shard", options->shard,
                    "Audit only shard K of N (K = 1..N): the cases whose index in the whole input is K-1 modulo N. "
                    "`auto` reads K and N from a Slurm job array, `auto/N` also from a Kubernetes Indexed Job, or "
                    "RAYVERIFY_SHARD_INDEX (0-based) and RAYVERIFY_TOTAL_SHARDS (docs/scaling_out.md). Needs "
                    "--report DIR, where the shard's state goes; `rayverify merge` combines the N shards into the "
                    "report of the whole run");
    return {sub, [options, command_line] { return run(*options, command_line); }};
}

}  // namespace rayverify::cli
