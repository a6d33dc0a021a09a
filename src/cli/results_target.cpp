// The input options shared by the commands that read cases (--corpus,
// --generate, --scene), and the target a results file stands for
// (--results FILE --contract SPEC --name NAME): audit, gate and explain.
#include <fmt/format.h>

#include <stdexcept>

#include "cli/commands.h"
#include "core/input_error.h"
#include "cli/shipped_libraries.h"
#include "core/target_name.h"
#include "corpus/external_program.h"
#include "scene/scene.h"

namespace rayverify::cli {

case_input select_input(const std::vector<std::string>& corpus, const std::vector<std::string>& generate) {
    if (!corpus.empty() && !generate.empty())
        throw input_error("", 0, "--generate", "give either --corpus or --generate, not both");
    case_input input;
    input.paths.assign(corpus.begin(), corpus.end());
    for (const std::string& text : generate) input.specs.push_back(parse_generate_spec(text));
    if (input.paths.empty() && input.specs.empty()) input.paths.emplace_back(default_corpus());
    return input;
}

case_stream case_input::open(shard_spec shard) const {
    return specs.empty() ? case_stream(paths, shard) : case_stream(specs, shard);
}

std::vector<corpus_case> scene_cases(const scene& s) {
    std::vector<corpus_case> cases;
    for (const scene_ray& r : generate_rays(s))
        for (int sphere : r.spheres) cases.push_back(case_for(s, r, sphere));
    return cases;
}

std::string fingerprint_of(std::span<const corpus_case> cases) {
    case_fingerprint fingerprint;
    for (const corpus_case& c : cases) fingerprint.add(c);
    return fingerprint.text();
}

void add_results_options(CLI::App* sub, results_options& options) {
    sub->add_option(
        "--results", options.file,
        "Answers computed outside rayverify for these cases (.csv, .jsonl, or .npy with its .json companion; "
        "docs/other-languages.md), judged as a variant named --name under --contract");
    CLI::Option* command = sub->add_option(
        "--command", options.command,
        "A program in any language that answers the cases (docs/other-languages.md): run once with /bin/sh -c, "
        "it reads batches of cases on stdin and answers each on stdout, in --format; judged as a variant named "
        "--name under --contract, in the one --precision given (double by default). It dying, hanging or "
        "answering garbage is an input error naming it and the case (exit 2)");
    sub->add_option("--contract", options.contract_spec,
                    "The contract of the --results or --command answers, as `rayverify variants` prints contracts, "
                    "e.g. query=line_roots, or query=nearest_hit with range=ray, ends=[) and inside=clamp joined by "
                    "commas");
    sub->add_option("--name", options.name,
                    "The name the --results or --command answers are reported under (one token)");
    sub->add_option("--format", options.format, "With --command: jsonl or csv")
        ->check(CLI::IsMember({"jsonl", "csv"}))
        ->needs(command)
        ->capture_default_str();
    sub->add_option("--command-timeout", options.command_timeout,
                    "Seconds a --command program, or an engine that runs as a program (node), may take over one "
                    "batch of 4096 cases before it is killed (default: 60 for --command, 300 for an engine, whose "
                    "first batch also starts node and loads the library)")
        ->check(finite_number(0.001, 86400));
    sub->add_option("--accuracy", options.accuracy,
                    "The accuracy every target's answers must have (the contract's accuracy clause): ulp:N (|t - t*| "
                    "within N ulp of t*), radius:X (|t - t*|·|d| within X radii) or distance:X (within X, in the "
                    "case's units); an answer on the right root but farther is `imprecise`, a disagreement "
                    "(any_hit targets return no t and are judged as before)");
    sub->add_option("--degenerate", options.degenerate,
                    "miss: every target is handed the degenerate casts (zero direction, NaN or infinite input or "
                    "bound, tmin > tmax) and must answer a miss, else `degenerate_hit` (the contract clause "
                    "degenerate=miss); invalid: such cases are invalid and not run (the default of every built-in)")
        ->check(CLI::IsMember({"miss", "invalid"}));
    sub->add_option("--engine", options.engines,
                    "An engine's library as its package installs it (`rayverify engines` lists them: Embree, "
                    "Bullet, ODE, three.js, ...), audited as a variant under its own name (repeatable)");
}

void declare_results_inputs(run_outputs& outputs, const results_options& options) {
    if (options.file.empty()) return;
    outputs.input(options.file, "--results");
    if (exchange_format_of(options.file) == exchange_format::npy)
        outputs.input(sidecar_of(options.file), "--results, its JSON companion");
}

namespace {

contract contract_from(const std::string& spec) {
    if (spec.empty())
        throw input_error("", 0, "--contract",
                          "answers computed outside rayverify need their contract, e.g. --contract query=line_roots");
    try {
        return parse_contract(spec);
    } catch (const std::invalid_argument& e) {
        throw input_error("", 0, "--contract", e.what());
    }
}

// Every answer with a hit carries each output beside t the contract names
// (an answer judged on what it does not give would be judged on nothing).
// The first such answer in the file is named.
void check_named_outputs(const contract& promises, const answer_book& book) {
    if (promises.outputs.point_error != point_bound::none)
        throw input_error("", 0, "--contract",
                          "a results file has no columns for a hit point's error bound: leave point_error out");
    const recorded_answer* first = nullptr;
    std::string first_id, missing;
    for (const auto& [id, a] : book.by_id) {
        if (a.roots.count <= 0 || (first && first->line < a.line)) continue;
        const char* lacks = promises.outputs.t_bounds && !a.t0_bounds ? "t0_lo t0_hi t1_lo t1_hi"
                            : gives_hit_point(promises) && !a.hit_point ? "px py pz"
                            : promises.outputs.normal && !a.normal     ? "nx ny nz"
                                                                        : nullptr;
        if (!lacks) continue;
        first = &a;
        first_id = id;
        missing = lacks;
    }
    if (first)
        throw input_error(book.source, first->line, missing,
                          fmt::format("answer '{}' is a hit without the outputs ({}) that --contract names", first_id,
                                      missing));
}

}  // namespace

audit_target outside_target(const std::string& name, const std::string& contract_spec, const std::string& citation,
                            precision prec) {
    if (name.empty())
        throw input_error("", 0, "--name", "answers computed outside rayverify need --name NAME (one token, no '/')");
    if (!is_target_name(name))
        throw input_error("", 0, "--name",
                          fmt::format("'{}' must be one token without spaces, '/', '#' or control characters",
                                      escaped_control(name)));
    if (find_builtin_variant(name))
        throw input_error("", 0, "--name", fmt::format("'{}' is a built-in variant's name: choose another", name));
    audit_target target;
    target.subject.name = name;
    target.subject.citation = citation;
    target.subject.formula = "(computed outside rayverify)";
    target.subject.promises = contract_from(contract_spec);
    // A spec has no tangent rule: the answers' count is all there is to say.
    if (target.subject.promises.reports_tangent) target.subject.promises.tangent_rule = "its answers say so";
    target.prec = prec;
    return target;
}

namespace {

// The target a results file stands for.
audit_target results_file_target(const results_options& options, const case_feed& feed) {
    contract_from(options.contract_spec);  // a bad contract before reading the file
    // The input first: what the file may answer bounds what is read of it.
    results_scope scope;
    std::vector<corpus_case> input;  // id and where it was read: all the matcher needs
    scope.input_fingerprint = feed([&](const corpus_case& c) {
        scope.add(c.id);
        corpus_case named;
        named.id = c.id;
        named.source = c.source;
        input.push_back(std::move(named));
    });
    results_file results = read_results(options.file, &scope);
    audit_target target = outside_target(options.name, options.contract_spec, "results file " + options.file, results.prec);
    answer_matcher matcher(results);
    for (const corpus_case& c : input) matcher.add(c);
    target.recorded = matcher.finish(scope.input_fingerprint);
    check_recorded_values(target.subject.promises, *target.recorded);
    check_named_outputs(target.subject.promises, *target.recorded);
    return target;
}

// Cases a program is sent at once: few enough to keep a batch's text small,
// enough that starting a batch costs nothing beside answering it.
constexpr std::size_t program_batch_cases = 4096;
// The longest a program may take over one batch unless --command-timeout
// says otherwise: a guard against a hang. An engine's batch takes well under
// a second; its 300 s are generous for a loaded machine.
constexpr double command_program_timeout = 60;
constexpr double engine_program_timeout = 300;

// Asks `program` for `cases` (one batch) and adds its answers to `book`, each
// numbered by its position among all the program's answers (`answered`
// came before this batch).
void ask_program(external_program& program, std::span<const corpus_case> cases, std::size_t answered,
                 answer_book& book) {
    const std::shared_ptr<const answer_book> answers = program.answer(cases);
    for (const auto& [id, a] : answers->by_id) {
        recorded_answer numbered = a;
        numbered.line += answered;
        book.by_id.emplace(id, numbered);
    }
}

// `target` (an outside target) answered by a program: the whole input sent
// batch by batch, each answer checked against its batch (corpus/external_program.h).
void answer_by_program(audit_target& target, const std::string& command, exchange_format format, double timeout,
                       const case_feed& feed) {
    external_program program(command, format, target.prec, timeout);
    auto book = std::make_shared<answer_book>();
    book->source = "command " + command;
    book->prec = target.prec;
    std::vector<corpus_case> batch;
    std::size_t answered = 0;
    const auto ask = [&] {
        ask_program(program, batch, answered, *book);
        answered += batch.size();
        batch.clear();
    };
    feed([&](const corpus_case& c) {
        batch.push_back(c);
        if (batch.size() == program_batch_cases) ask();
    });
    if (!batch.empty()) ask();
    program.finish();  // nothing may follow its last answer
    check_recorded_values(target.subject.promises, *book);
    check_named_outputs(target.subject.promises, *book);
    target.recorded = std::move(book);
}

// `target` answered by a program chunk by chunk as the audit judges them
// (audit_target::answer_chunk): one batch per chunk, each answer checked
// against its batch, and the book holds that batch's answers only.
void answer_by_program_per_chunk(audit_target& target, const std::string& command, exchange_format format,
                                 double timeout) {
    struct program_answers {
        program_answers(const std::string& command, exchange_format format, precision prec, double timeout)
            : program(command, format, prec, timeout) {}
        external_program program;
        std::shared_ptr<answer_book> book = std::make_shared<answer_book>();
        std::size_t answered = 0;
    };
    auto state = std::make_shared<program_answers>(command, format, target.prec, timeout);
    state->book->source = "command " + command;
    state->book->prec = target.prec;
    target.recorded = state->book;
    const contract promises = target.subject.promises;
    target.answer_chunk = [state, promises](std::span<const corpus_case> cases) {
        answer_book& book = *state->book;
        book.by_id.clear();
        for (std::size_t begin = 0; begin < cases.size(); begin += program_batch_cases) {
            const std::size_t end = std::min(cases.size(), begin + program_batch_cases);
            ask_program(state->program, cases.subspan(begin, end - begin), state->answered + begin, book);
        }
        state->answered += cases.size();
        check_recorded_values(promises, book);
        check_named_outputs(promises, book);
    };
    target.finish_answers = [state] { state->program.finish(); };
}

// The one precision a --command program answers in.
precision program_precision(const std::vector<std::string>& precisions, std::optional<precision> scene_precision) {
    if (scene_precision) return *scene_precision;
    if (precisions.size() > 1)
        throw input_error("", 0, "--precision", "a --command program answers in one precision: give --precision once");
    return precisions.empty() ? precision::binary64 : named_precision(precisions.front());
}

}  // namespace

std::vector<audit_target> outside_targets(const results_options& options, const std::vector<std::string>& precisions,
                                          const case_feed& feed, std::optional<precision> scene_precision,
                                          programs_answer how) {
    if (!options.file.empty() && !options.command.empty())
        throw input_error("", 0, "--command", "give either --results or --command, not both");
    if (options.file.empty() && options.command.empty())
        for (const auto& [given, option] : {std::pair{!options.contract_spec.empty(), "--contract"},
                                            std::pair{!options.name.empty(), "--name"}})
            if (given)
                throw input_error("", 0, option,
                                  fmt::format("{} is for the answers of --results or --command: give one of those",
                                              option));
    std::vector<audit_target> targets;
    if (!options.file.empty()) targets.push_back(results_file_target(options, feed));
    if (!options.command.empty()) {
        contract_from(options.contract_spec);  // a bad contract before the program starts
        audit_target target = outside_target(options.name, options.contract_spec, "command " + options.command,
                                             program_precision(precisions, scene_precision));
        const double timeout = options.command_timeout.value_or(command_program_timeout);
        if (how == programs_answer::chunk_by_chunk)
            answer_by_program_per_chunk(target, options.command, *exchange_format_from_name(options.format), timeout);
        else
            answer_by_program(target, options.command, *exchange_format_from_name(options.format), timeout, feed);
        targets.push_back(std::move(target));
    }
    for (const shipped_library& lib : requested_libraries(options.engines)) {
        if (lib.how != shipped_library::runner::program) continue;  // a plugin: select_targets
        const precision prec = lib.precisions.front();
        const std::string prec_name(precision_name(prec));
        if (!scene_precision && !precisions.empty() &&
            std::find(precisions.begin(), precisions.end(), prec_name) == precisions.end())
            continue;
        audit_target target = outside_target(lib.name, lib.contract,
                                             fmt::format("{} {} ({}), {} through {}", lib.identity.name,
                                                         lib.identity.version, lib.identity.source, lib.api,
                                                         lib.command),
                                             prec);
        target.subject.library = lib.identity;
        const double timeout = options.command_timeout.value_or(engine_program_timeout);
        if (how == programs_answer::chunk_by_chunk && !scene_precision)
            answer_by_program_per_chunk(target, lib.command, exchange_format::jsonl, timeout);
        else if (!scene_precision || *scene_precision == prec)
            answer_by_program(target, lib.command, exchange_format::jsonl, timeout, feed);
        else
            target.recorded = std::make_shared<answer_book>();  // no answers: the scene audit says why
        targets.push_back(std::move(target));
    }
    return targets;
}

std::vector<audit_target> targets_with_results(const std::vector<std::string>& variant_names,
                                               const std::vector<std::string>& plugin_paths,
                                               const std::vector<std::string>& precisions,
                                               const plugin_isolation& isolation, const results_options& options,
                                               const std::vector<audit_target>& outside) {
    std::vector<audit_target> targets;
    const bool only_outside = !outside.empty() && variant_names.empty() && plugin_paths.empty() &&
                              options.engines.empty();
    if (!only_outside) targets = select_targets(variant_names, plugin_paths, precisions, isolation, options.engines);
    if (!options.file.empty()) {
        const std::string prec = precision_name(outside.front().prec);
        if (!precisions.empty() && std::find(precisions.begin(), precisions.end(), prec) == precisions.end())
            throw input_error("", 0, "--precision",
                              fmt::format("the --results answers are in {}, which --precision leaves out", prec));
    }
    append_outside_targets(targets, outside);
    check_fp_environment_targets(isolation.environment, targets);
    require_clauses(targets, options);
    return targets;
}

void require_clauses(std::span<audit_target> targets, const std::string& accuracy, const std::string& degenerate) {
    std::optional<accuracy_requirement> required;
    if (!accuracy.empty()) {
        try {
            required = parse_accuracy(accuracy);
        } catch (const std::invalid_argument& e) {
            throw input_error("", 0, "--accuracy", e.what());
        }
    }
    for (audit_target& t : targets) {
        contract& promises = t.subject.promises;
        if (required && promises.query != query_kind::any_hit) promises.accuracy = *required;
        if (!degenerate.empty()) promises.degenerate_is_miss = degenerate == "miss";
    }
}

void require_clauses(std::vector<audit_target>& targets, const results_options& options) {
    require_clauses(targets, options.accuracy, options.degenerate);
}

void finish_outside_answers(const std::vector<audit_target>& targets) {
    for (const audit_target& t : targets)
        if (t.finish_answers) t.finish_answers();
}

void append_outside_targets(std::vector<audit_target>& targets, const std::vector<audit_target>& outside) {
    for (const audit_target& o : outside) {
        for (const audit_target& t : targets)
            if (t.subject.name == o.subject.name)
                throw input_error("", 0, "--name", fmt::format("two targets named '{}'", t.subject.name));
        targets.push_back(o);
    }
}

}  // namespace rayverify::cli
