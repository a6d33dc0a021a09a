// `rayverify builds SOURCE...` (docs/builds.md): one intersector source built
// under every compiler and flag set of a matrix into isolated plugins
// (plugin/plugin_builds), audited together beside the exact answer, each build's
// answers compared bit for bit with the reference build's
// (compare/build_comparison), each build that changes them bisected to the
// smallest set of its flags that reproduces the change, the report rendered
// by report/builds_report; and with --baseline, chosen builds gated.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli/app.h"
#include "plugin/plugin_builds.h"
#include "cli/commands.h"
#include "compare/build_comparison.h"
#include "compare/gate.h"
#include "core/input_error.h"
#include "report/audit_pass.h"
#include "report/audit_report.h"
#include "report/builds_report.h"
#include "report/gate_report.h"
#include "report/shard_state.h"

namespace rayverify::cli {
namespace {

namespace fs = std::filesystem;

struct builds_options {
    std::vector<std::string> sources, harness, include_dirs, defines, libraries;
    std::vector<std::string> compilers, flag_sets, standards;
    std::vector<std::string> corpus, generate, precisions;
    std::string report_dir, cache_dir;
    bool plots = false;
    bool no_bisect = false;
    std::size_t examples = 3;
    double plugin_timeout = 10;
    unsigned jobs = 2;
    std::string baseline;
    bool update = false;
    std::vector<std::string> gate_builds;
};

// The changed answers a bisect runs its candidates on, at most, per precision.
constexpr std::size_t bisect_cases = 2000;

void check_source_files(const std::vector<std::string>& files, const std::string& field) {
    for (const std::string& f : files) {
        std::error_code error;
        if (!fs::exists(f, error)) throw input_error(f, 0, field, "no such file");
        if (!fs::is_regular_file(f, error)) throw input_error(f, 0, field, "is not a regular file");
        if (!std::ifstream(f)) throw input_error(f, 0, field, "cannot open for reading");
        if (!language_of(f))
            throw input_error(f, 0, field, "is neither a C source (.c) nor a C++ source (.cc, .cpp, .cxx, .c++, .C)");
    }
}

// "NAME=FLAGS" or "FLAGS": the build's own name when given.
std::pair<std::string, std::vector<std::string>> named_flag_set(const std::string& text) {
    const std::size_t equals = text.find('=');
    const std::size_t first = text.find_first_not_of(" \t");
    if (equals != std::string::npos && first != std::string::npos && text[first] != '-') {
        const std::string name = text.substr(first, equals - first);
        if (!is_target_name(name) || name.find_first_of(" \t") != std::string::npos)
            throw input_error("", 0, "--flags", fmt::format("'{}' is not a build name (one word, no '/' or '#')", name));
        return {name, flag_words(text.substr(equals + 1))};
    }
    return {std::string(), flag_words(text)};
}

// The matrix: the reference build first, then each compiler × flag set.
std::vector<build_spec> matrix_specs(const builds_options& options, std::vector<compiler_driver>& compilers) {
    std::vector<std::string> wanted = options.compilers.empty() ? std::vector<std::string>{"gcc", "clang"}
                                                                : options.compilers;
    std::vector<std::string> missing;
    for (const std::string& name : wanted) {
        if (std::any_of(compilers.begin(), compilers.end(), [&](const compiler_driver& c) { return c.name == name; }))
            continue;
        if (std::optional<compiler_driver> found = find_compiler(name))
            compilers.push_back(*found);
        else
            missing.push_back(name);
    }
    for (const std::string& name : missing)
        terminal::note(fmt::format("builds: {} is not on this machine: its builds are skipped (tools/setup.sh "
                                   "installs gcc and clang)",
                                   name));
    if (compilers.empty())
        throw input_error("", 0, "--compiler",
                          fmt::format("none of the compilers asked for is on this machine ({})", fmt::join(wanted, ", ")));
    std::vector<build_spec> specs;
    // The reference: gcc's strict build whatever --compiler chose, else the first compiler's.
    const auto gcc = std::find_if(compilers.begin(), compilers.end(), [](const compiler_driver& c) { return c.name == "gcc"; });
    // (gcc was looked for already when --compiler asked for it.)
    const bool gcc_missing = std::find(missing.begin(), missing.end(), "gcc") != missing.end();
    const std::optional<compiler_driver> reference_gcc =
        gcc != compilers.end() ? std::optional(*gcc) : gcc_missing ? std::nullopt : find_compiler("gcc");
    build_spec reference;
    if (reference_gcc) {
        reference.compiler = *reference_gcc;
    } else {
        reference.compiler = compilers.front();
        terminal::note(fmt::format("builds: gcc is not on this machine: the reference build is {}'s", reference.compiler.name));
    }
    reference.flags = flag_words(reference_flags_text);
    reference.name = build_name(reference.compiler.name, reference.flags);
    reference.reference = true;
    specs.push_back(reference);
    const std::vector<std::string> sets = options.flag_sets.empty() ? default_flag_sets() : options.flag_sets;
    for (const compiler_driver& compiler : compilers)
        for (const std::string& set : sets) {
            auto [name, flags] = named_flag_set(set);
            check_build_flags(flags, "--flags");
            build_spec spec;
            spec.compiler = compiler;
            spec.flags = flags;
            spec.name = name.empty() ? build_name(compiler.name, flags)
                                     : (compilers.size() > 1 ? compiler.name + "-" + name : name);
            if (spec.compiler.name == reference.compiler.name && spec.flags == reference.flags) continue;
            if (std::any_of(specs.begin(), specs.end(), [&](const build_spec& s) { return s.name == spec.name; }))
                throw input_error("", 0, "--flags", fmt::format("two builds named '{}'", spec.name));
            specs.push_back(spec);
        }
    return specs;
}

std::string flags_text(const std::vector<std::string>& flags) { return fmt::format("{}", fmt::join(flags, " ")); }

// A build's plugin loaded in a child process of its own, named after the build.
variant load_build(const built_plugin& b, double timeout) {
    plugin_isolation isolation;
    isolation.child_process = true;
    isolation.timeout_seconds = timeout;
    variant v = load_plugin(b.plugin, isolation);
    v.name = b.spec.name;
    v.build = fmt::format("{} {} (rayverify builds)", b.spec.compiler.name, flags_text(b.spec.flags));
    return v;
}

// The answers of `v` on every change of `differences` (per precision), each
// compared with the build's: true where they are the same.
// `changed_cases[k]`: the cases of differences[k]'s changes, in order.
std::vector<bool> matches_of(const variant& v, const std::vector<const build_difference*>& differences,
                             const std::vector<std::vector<corpus_case>>& changed_cases,
                             const std::vector<precision>& precisions) {
    std::vector<bool> matches;
    for (std::size_t k = 0; k < differences.size(); ++k) {
        const std::vector<corpus_case>& cases = changed_cases[k];
        const std::vector<audit_target> target = {audit_target{v, precisions[k]}};
        const std::vector<std::vector<given_answer>> given = batch_answers(cases, target);
        for (std::size_t i = 0; i < cases.size(); ++i) {
            const audited_case judged =
                audit_case(cases[i], target, given.empty() ? std::span<const given_answer>{} : given[i]);
            matches.push_back(same_answer(judged.outcomes[0].output, differences[k]->changes[i].answer));
        }
    }
    return matches;
}

// The bisect of one build: the smallest set of its flag components whose
// build gives its answers on the cases where it changed them.
build_bisect_result bisect_build(const built_plugin& build, bool loads_with_ftz_daz,
                                 const std::vector<const build_difference*>& differences,
                                 const std::vector<precision>& precisions, const builds_options& options,
                                 const build_sources& sources, const fs::path& cache) {
    build_bisect_result result;
    std::vector<flag_component> components = flag_components(build.spec, loads_with_ftz_daz);
    std::vector<std::vector<corpus_case>> changed_cases;
    for (const build_difference* d : differences) {
        result.cases += d->changes.size();
        changed_cases.emplace_back();
        for (const auto& change : d->changes) changed_cases.back().push_back(change.source);
    }
    std::map<std::vector<std::size_t>, std::optional<std::vector<bool>>> tried;
    // The matches of the build of `components` restricted to `subset`.
    const auto matches = [&](const std::vector<flag_component>& from,
                             const std::vector<std::size_t>& subset) -> std::optional<std::vector<bool>> {
        std::vector<flag_component> chosen;
        for (std::size_t i : subset) chosen.push_back(from[i]);
        const build_spec spec = build_of_components(build.spec, chosen);
        const std::vector<built_plugin> built = build_plugins({&spec, 1}, sources, cache, 1);
        ++result.builds_tried;
        if (!built[0].built()) return std::nullopt;
        try {
            return matches_of(load_build(built[0], options.plugin_timeout), differences, changed_cases, precisions);
        } catch (const input_error&) {
            return std::nullopt;  // a candidate that does not load or fails does not reproduce
        }
    };
    const auto all_true = [](const std::optional<std::vector<bool>>& m, const std::vector<std::size_t>* only) {
        if (!m) return false;
        if (only == nullptr) return std::all_of(m->begin(), m->end(), [](bool b) { return b; });
        return std::all_of(only->begin(), only->end(), [&](std::size_t i) { return (*m)[i]; });
    };
    std::vector<std::size_t> everything(components.size());
    for (std::size_t i = 0; i < everything.size(); ++i) everything[i] = i;
    result.searched = "the components of its flags";
    std::optional<std::vector<bool>> whole = matches(components, everything);
    tried[everything] = whole;
    if (!all_true(whole, nullptr)) {
        // The components together are not the build (a flag does more than
        // its parts): its own flags, as given, instead.
        components.clear();
        for (const std::string& f : build.spec.flags) components.push_back({f, {f}, false});
        everything.resize(components.size());
        tried.clear();
        whole = matches(components, everything);
        tried[everything] = whole;
        result.searched = "its own flags (their components together did not give its answers)";
        if (!all_true(whole, nullptr)) {
            result.failure = "rebuilt from its own flags, it does not give its own answers again (answers that "
                             "vary from build to build): nothing to bisect";
            for (const flag_component& c : components) result.components.push_back(c.label);
            return result;
        }
    }
    for (const flag_component& c : components) result.components.push_back(c.label);
    const auto search = [&](const std::vector<std::size_t>* only) {
        return smallest_reproducing_subset(components.size(), [&](const std::vector<std::size_t>& subset) {
            auto known = tried.find(subset);
            if (known == tried.end()) known = tried.emplace(subset, matches(components, subset)).first;
            return all_true(known->second, only);
        });
    };
    const auto labels = [&](const std::vector<std::size_t>& subset) {
        std::vector<std::string> out;
        for (std::size_t i : subset) out.push_back(components[i].label);
        return out;
    };
    result.smallest = labels(search(nullptr));
    // Each kind of verdict flip on its own cases.
    std::map<std::pair<verdict_kind, verdict_kind>, std::vector<std::size_t>> by_flip;
    std::size_t position = 0;
    for (const build_difference* d : differences)
        for (const auto& change : d->changes) {
            if (change.reference_verdict != change.build_verdict)
                by_flip[{change.reference_verdict, change.build_verdict}].push_back(position);
            ++position;
        }
    std::vector<flip_count> counts;
    for (const auto& [kinds, cases] : by_flip) counts.emplace_back(kinds, cases.size());
    for (const auto& [kinds, count] : flips_worst_first(counts))
        result.flips.push_back({kinds.first, kinds.second, count, labels(search(&by_flip.at(kinds)))});
    return result;
}

// The pinned builds' figures against a baseline (gate), or the baseline
// written from them (--update): one baseline entry per build and precision.
int gate_builds(const builds_options& options, const case_input& input, const std::vector<audit_target>& targets,
                const std::vector<build_row>& rows, run_outputs& files, std::string& printed) {
    std::vector<audit_target> pinned;
    for (const std::string& name : options.gate_builds)
        if (std::none_of(rows.begin(), rows.end(), [&](const build_row& r) { return r.name == name; })) {
            std::vector<std::string> names;
            for (const build_row& r : rows) names.push_back(r.name);
            throw input_error("", 0, "--gate-build",
                              fmt::format("no build is named '{}'; the builds: {}", name, fmt::join(names, ", ")));
        }
    for (const build_row& r : rows) {
        const bool chosen = options.gate_builds.empty() ||
                            std::find(options.gate_builds.begin(), options.gate_builds.end(), r.name) !=
                                options.gate_builds.end();
        if (!chosen) continue;
        if (r.status != build_row::outcome::ran)
            throw input_error("", 0, "--gate-build",
                              fmt::format("build '{}' is gated but did not run: {}", r.name, r.failure));
        for (const audit_target& t : targets)
            if (t.subject.name == r.name) pinned.push_back(t);
    }
    const fs::path path(options.baseline);
    std::error_code error;
    const bool exists = fs::exists(path, error);
    if (!exists && !options.update)
        throw input_error(options.baseline, 0, "--baseline",
                          "no such baseline; create it with `rayverify builds ... --baseline FILE --update`");
    const baseline base =
        exists ? parse_baseline(options.baseline, read_text_file(path, "--baseline")) : new_baseline();
    std::vector<corpus_case> cases;
    {
        case_stream stream = input.open();
        std::vector<corpus_case> chunk;
        std::vector<std::size_t> indices;
        while (stream.next(chunk, indices)) {
            cases.insert(cases.end(), chunk.begin(), chunk.end());
            chunk.clear();
            indices.clear();
        }
    }
    const gate_run run = run_gate(cases, pinned, base, options.examples, 1);
    if (options.update) {
        files.file(path, "--baseline").stream()
            << format_baseline(updated_baseline(base, run.current, run.configurations, run.contracts));
        printed += fmt::format("gate: {} {}: {} figures of {} build target(s) over {} cases\n",
                               exists ? "updated" : "created", options.baseline, run.current.size(), pinned.size(),
                               cases.size());
        return exit_ok;
    }
    printed += render_gate_text(run, cases);
    return run.result.passed() ? exit_ok : exit_findings;
}

int run(const builds_options& options, const std::string& command_line) {
    check_source_files(options.sources, "SOURCE");
    check_source_files(options.harness, "--harness");
    for (const std::string& d : options.include_dirs) {
        std::error_code error;
        if (!fs::is_directory(d, error)) throw input_error(d, 0, "-I", "no such directory");
    }
    if (options.update && options.baseline.empty())
        throw input_error("", 0, "--update", "--update writes the baseline: add --baseline FILE");
    if (!options.gate_builds.empty() && options.baseline.empty())
        throw input_error("", 0, "--gate-build", "a build is gated against a baseline: add --baseline FILE");
    if (options.plots && options.report_dir.empty())
        throw input_error("", 0, "--plots", "the plots are drawn into the report directory: add --report DIR");
    std::vector<compiler_driver> compilers;
    const std::vector<build_spec> specs = matrix_specs(options, compilers);
    build_sources sources;
    for (const std::string& s : options.sources) sources.sources.emplace_back(s);
    for (const std::string& s : options.harness) sources.harness.emplace_back(s);
    sources.include_dirs = options.include_dirs;
    sources.defines = options.defines;
    for (const std::string& l : options.libraries)
        if (l.empty() || l.find_first_of(" \t/") != std::string::npos || l.starts_with("-"))
            throw input_error("", 0, "--link", fmt::format("'{}' is not a library name (the NAME of -lNAME)", l));
    sources.libraries = options.libraries;
    for (const std::string& standard : options.standards) {
        const bool cxx = standard.starts_with("c++") || standard.starts_with("gnu++");
        if (!cxx && !standard.starts_with("c") && !standard.starts_with("gnu"))
            throw input_error("", 0, "--std", fmt::format("'{}' is no C or C++ standard (c99, c17, c++17, gnu++20, ...)", standard));
        std::string& chosen = cxx ? sources.cxx_standard : sources.c_standard;
        if (!chosen.empty()) throw input_error("", 0, "--std", fmt::format("two {} standards given", cxx ? "C++" : "C"));
        chosen = standard;
    }
    const fs::path cache = options.cache_dir.empty() ? default_build_cache() : fs::path(options.cache_dir);

    const std::vector<built_plugin> built = build_plugins(specs, sources, cache, options.jobs);
    std::size_t compiled = 0, reused = 0;
    for (const built_plugin& b : built) (b.cached ? reused : compiled) += b.built() ? 1 : 0;
    terminal::note(fmt::format("builds: {} builds ({} compiled now, {} from the cache in {}, {} not built)", built.size(),
                               compiled, reused, cache.string(), built.size() - compiled - reused));
    if (!built.front().built())
        throw input_error(options.sources.front(), 0, "SOURCE",
                          fmt::format("the reference build ({} {}) does not compile: {}", built.front().spec.compiler.name,
                                      flags_text(built.front().spec.flags), built.front().failure));

    // Each build loaded in a child process of its own: a fast-math build's
    // library changes the floating-point environment when it loads.
    std::vector<build_row> rows;
    std::vector<variant> variants;
    std::vector<std::size_t> row_of_variant;
    for (const built_plugin& b : built) {
        build_row row;
        row.name = b.spec.name;
        row.compiler = b.spec.compiler.name;
        row.compiler_version = b.spec.compiler.version;
        row.flags = flags_text(b.spec.flags);
        row.reference = b.spec.reference;
        row.cached = b.cached;
        row.commands = b.command_lines;
        row.plugin = b.plugin.string();
        if (!b.built()) {
            row.status = b.refused_by_source ? build_row::outcome::refused_by_source : build_row::outcome::did_not_compile;
            row.failure = b.failure;
        } else {
            try {
                variants.push_back(load_build(b, options.plugin_timeout));
                row.fp_environment = variants.back().fp_environment;
                row_of_variant.push_back(rows.size());
            } catch (const input_error& e) {
                if (b.spec.reference) throw;
                row.status = build_row::outcome::did_not_load;
                row.failure = e.what();
            }
        }
        rows.push_back(row);
    }

    // The cases: as given, else the shipped corpus (its segments when every
    // build casts segments only).
    std::vector<std::string> corpus = options.corpus;
    if (corpus.empty() && options.generate.empty()) {
        const bool segments_only = std::all_of(variants.begin(), variants.end(), [](const variant& v) {
            return v.promises.takes_segment_ends;
        });
        corpus.push_back(segments_only ? (fs::path(default_corpus()) / "segments").string() : default_corpus());
    }
    const case_input input = select_input(corpus, options.generate);

    // Every output declared before the audit, committed once all are complete.
    audit_outputs outputs;
    for (const auto* list : {&options.sources, &options.harness})
        declare_inputs(outputs.files, {list->begin(), list->end()}, "SOURCE");
    declare_inputs(outputs.files, {input.paths.begin(), input.paths.end()}, "--corpus");
    if (!options.baseline.empty() && !options.update)
        declare_inputs(outputs.files, {fs::path(options.baseline)}, "--baseline");
    outputs.open_report(fs::path(options.report_dir), "--report");

    // The audit, again without a build that failed in it (named, no figures).
    audit_state audited{std::vector<audit_target>{}};
    std::vector<audit_target> targets;
    std::optional<build_comparison> comparison;
    for (;;) {
        targets = targets_in_precisions(variants, options.precisions);
        if (targets.empty()) throw input_error("", 0, "--precision", "no build runs in the chosen precision");
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        for (std::size_t t = 0; t < targets.size(); ++t) {
            if (targets[t].subject.name == rows.front().name) continue;
            for (std::size_t r = 0; r < targets.size(); ++r)
                if (targets[r].subject.name == rows.front().name && targets[r].prec == targets[t].prec)
                    pairs.emplace_back(t, r);
        }
        comparison.emplace(pairs, bisect_cases);
        case_stream stream = input.open();
        const case_source next = [&](std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
            return stream.next(cases, indices);
        };
        try {
            audited = run_audit_pass(next, targets, 1, !options.report_dir.empty(), nullptr, {}, nullptr,
                                     [&](const audited_case& c, std::size_t index) { comparison->add(c, index); });
            break;
        } catch (const plugin_failure& failure) {
            std::size_t failed = variants.size();
            for (std::size_t v = 0; v < variants.size(); ++v)
                if (rows[row_of_variant[v]].plugin == failure.file()) failed = v;
            if (failed == variants.size() || rows[row_of_variant[failed]].reference) throw;
            build_row& row = rows[row_of_variant[failed]];
            row.status = build_row::outcome::failed_in_audit;
            row.failure = failure.what();
            terminal::note(fmt::format("builds: {} failed while audited, and is left out: {}", row.name, row.failure));
            variants.erase(variants.begin() + static_cast<std::ptrdiff_t>(failed));
            row_of_variant.erase(row_of_variant.begin() + static_cast<std::ptrdiff_t>(failed));
        }
    }

    // The bisect of every build that changed answers.
    if (!options.no_bisect)
        for (std::size_t v = 0; v < variants.size(); ++v) {
            build_row& row = rows[row_of_variant[v]];
            if (row.reference) continue;
            std::vector<const build_difference*> changed;
            std::vector<precision> precisions;
            for (const build_difference& d : comparison->differences())
                if (targets[d.target].subject.name == row.name && !d.changes.empty()) {
                    changed.push_back(&d);
                    precisions.push_back(targets[d.target].prec);
                }
            if (changed.empty()) continue;
            const auto b = std::find_if(built.begin(), built.end(), [&](const built_plugin& p) { return p.spec.name == row.name; });
            row.bisect = bisect_build(*b, variants[v].fp_environment.find("FTZ") != std::string::npos, changed, precisions,
                                      options, sources, cache);
        }

    // The report: the audit's, with the builds' section.
    const std::size_t cases = audited.audit.cases;
    const nlohmann::ordered_json builds = builds_json(rows, targets, comparison->differences(), cases, options.examples);
    std::string printed = render_builds_text(builds);
    int gate_status = exit_ok;
    if (!options.baseline.empty()) {
        gate_status = gate_builds(options, input, targets, rows, outputs.files, printed);
    }
    run_context context{recorded_command(command_line), {}, {}};
    for (const auto& p : input.paths) context.corpus_paths.push_back(p.string());
    for (const generate_spec& s : input.specs) context.generated.push_back(s.text());
    const audit_totals totals = audited.audit.finish(1);
    std::optional<nlohmann::ordered_json> report;
    if (outputs.report) {
        report = audit_report_document(audited, totals, context, 1);
        (*report)["builds"] = builds;
    }
    publish_audit(totals, std::move(report), outputs, options.plots, {}, printed);
    if (!options.baseline.empty()) return gate_status;
    bool findings = false;
    for (const build_row& r : rows) findings = findings || r.status == build_row::outcome::failed_in_audit;
    for (const build_difference& d : comparison->differences()) findings = findings || d.verdicts_flipped() > 0;
    return findings ? exit_findings : exit_ok;
}

}  // namespace

command add_builds_command(CLI::App& app, const std::string& command_line) {
    auto options = std::make_shared<builds_options>();
    auto* sub = app.add_subcommand(
        "builds",
        "Build one intersector source (C or C++, with the plugin ABI's entry points) under every compiler and flag "
        "set of a matrix, audit the builds side by side beside the exact answer, compare each build's answers with "
        "the reference build's (gcc " +
            std::string(reference_flags_text) +
            ") and bisect each build that changes them to the flags that do. Exit 1 when a build flips a verdict "
            "or fails while audited (with --baseline: when the gate fails)");
    sub->add_option("sources", options->sources, "C or C++ sources built under each build's flags")
        ->required()
        ->type_name("SOURCE...");
    sub->add_option("--harness", options->harness,
                    "A source compiled with the reference flags in every build (the plugin's glue, so that only "
                    "the function under test changes with the build); repeatable");
    sub->add_option("-I,--include-dir", options->include_dirs, "Include directory for every compile (repeatable)");
    sub->add_option("-D,--define", options->defines, "Macro NAME or NAME=VALUE for every compile (repeatable)");
    sub->add_option("--link", options->libraries,
                    "A library the plugin links, -lNAME (repeatable): an engine adapter's library as installed");
    sub->add_option("--std", options->standards,
                    "The language standard of every compile of a C or of a C++ source, e.g. --std c++17 (clang 14 "
                    "compiles C++ as gnu++14 by default); once per language");
    sub->add_option("--compiler", options->compilers, "gcc or clang (repeatable; default: both)")
        ->check(CLI::IsMember({"gcc", "clang"}));
    sub->add_option("--flags", options->flag_sets,
                    "A flag set, e.g. --flags=\"-O3 -ffast-math\" or --flags=\"release=-O3 -ffast-math\" (a name for "
                    "the build); repeatable. Default: -O0, -O2, -O3, -O2 -march=native, -O2 -mfma "
                    "-ffp-contract=fast, -O2 -ffast-math, -Ofast. Flags that inject code (-include, -fplugin, "
                    "-specs, -B, -wrapper, @file) are refused")
        ->type_name("[NAME=]FLAGS");
    sub->add_option("--corpus", options->corpus,
                    "Corpus file or directory (repeatable). Default: the shipped corpus, or its segments/ when "
                    "every build casts segments only");
    sub->add_option("--generate", options->generate, "Generated cases instead of a corpus: FAMILY:COUNT[:SEED]");
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember(precision_names()));
    sub->add_option("--report", options->report_dir,
                    "Directory for report.json (with its \"builds\" section), report.md and summary.txt");
    sub->add_flag("--plots", options->plots, "With --report: also draw the plots, builds.png among them");
    sub->add_option("--cache", options->cache_dir,
                    "Build cache directory (default: $XDG_CACHE_HOME/rayverify/builds or ~/.cache/rayverify/builds)");
    sub->add_option("--jobs", options->jobs, "Builds compiled at a time (default 2)")->check(whole_number(1, 64));
    sub->add_flag("--no-bisect", options->no_bisect, "Do not bisect the builds that change answers");
    sub->add_option("--examples", options->examples, "Flipped cases shown per build and precision (default 3)")
        ->check(whole_number(0, 1000));
    sub->add_option("--plugin-timeout", options->plugin_timeout,
                    "Seconds a build may take over one call (or over loading) before it is stopped and its row fails")
        ->check(finite_number(0.001, 86400))
        ->capture_default_str();
    sub->add_option("--baseline", options->baseline,
                    "Gate the builds against this baseline (gate's format: one entry per build and precision)");
    sub->add_option("--gate-build", options->gate_builds,
                    "With --baseline: gate only this build (repeatable; default: every build), e.g. your release flags");
    sub->add_flag("--update", options->update, "With --baseline: write the baseline from this run instead");
    return {sub, [options, command_line] { return run(*options, command_line); }};
}

}  // namespace rayverify::cli
