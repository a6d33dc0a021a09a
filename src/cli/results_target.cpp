// The input options shared by the commands that read cases (--corpus,
// --generate, --scene), and the target a results file stands for
// (--results FILE --contract SPEC --name NAME): audit, gate and explain.
#include <fmt/format.h>

#include <stdexcept>

#include "cli/commands.h"
#include "core/input_error.h"
#include "core/target_name.h"
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
    CLI::Option* results = sub->add_option(
        "--results", options.file,
        "Answers computed outside rayverify for these cases (.csv, .jsonl, or .npy with its .json companion; "
        "docs/other-languages.md), judged as a variant named --name under --contract");
    sub->add_option("--contract", options.contract_spec,
                    "The contract of the --results answers, as `rayverify variants` prints contracts, e.g. "
                    "query=line_roots, or query=nearest_hit with range=ray, ends=[) and inside=clamp joined by "
                    "commas")
        ->needs(results);
    sub->add_option("--name", options.name, "The name the --results answers are reported under (one token)")
        ->needs(results);
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

std::optional<audit_target> results_target(const results_options& options,
                                           const std::function<std::string(const case_sink&)>& feed) {
    if (options.file.empty()) return std::nullopt;
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

std::vector<audit_target> targets_with_results(const std::vector<std::string>& variant_names,
                                               const std::vector<std::string>& plugin_paths,
                                               const std::vector<std::string>& precisions,
                                               const plugin_isolation& isolation,
                                               const std::optional<audit_target>& results) {
    if (!results) return select_targets(variant_names, plugin_paths, precisions, isolation);
    const std::string prec = precision_name(results->prec);
    if (!precisions.empty() && std::find(precisions.begin(), precisions.end(), prec) == precisions.end())
        throw input_error("", 0, "--precision",
                          fmt::format("the --results answers are in {}, which --precision leaves out", prec));
    std::vector<audit_target> targets;
    if (!variant_names.empty() || !plugin_paths.empty())
        targets = select_targets(variant_names, plugin_paths, precisions, isolation);
    for (const audit_target& t : targets)
        if (t.subject.name == results->subject.name)
            throw input_error("", 0, "--name", fmt::format("two targets named '{}'", t.subject.name));
    targets.push_back(*results);
    return targets;
}

}  // namespace rayverify::cli
