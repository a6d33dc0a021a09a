#include <fmt/format.h>

#include <cmath>
#include <sstream>

#include "compare/error_figures.h"
#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "intersectors/registry.h"
#include "intersectors/traced_variants.h"
#include "oracle/ideal_arithmetic.h"
#include "report/audit_report.h"

namespace rayverify::cli {
namespace {

struct explain_options {
    std::vector<std::string> values;  // 10 numbers, or a corpus line
    std::string case_id;
    std::vector<std::string> corpus;
    std::vector<std::string> variants;
    std::vector<std::string> plugins;
    plugin_isolation isolation;
    std::vector<std::string> precisions;
    results_options results;
    bool no_steps = false;  // leave out the intermediates of each variant's formula
};

constexpr const char* field_names[10] = {"ox", "oy", "oz", "dx", "dy", "dz", "cx", "cy", "cz", "r"};

// The case from the command line: "ox oy oz dx dy dz cx cy cz r" or a whole
// corpus line "id family ox ... r [tmin tmax]", as one argument or many.
corpus_case case_from_arguments(const std::vector<std::string>& values) {
    std::vector<std::string> tokens;
    for (const std::string& v : values) {
        std::istringstream words(v);
        for (std::string w; words >> w;) tokens.push_back(w);
    }
    if (tokens.size() > 2 && tokens[2] == "segment") {
        // A segment's corpus line, read as a corpus file reads it.
        std::string line;
        for (const std::string& t : tokens) line += t + ' ';
        std::vector<corpus_case> cases = parse_corpus("<command line>", line, false);
        cases.front().source = "<command line>";
        return cases.front();
    }
    corpus_case c;
    c.id = "command-line";
    c.source = "<command line>";
    std::size_t first = 0;
    if (tokens.size() == 12 || tokens.size() == 14) {
        c.id = tokens[0];
        c.family = tokens[1] == "-" ? "" : tokens[1];
        first = 2;
    } else if (tokens.size() != 10) {
        throw input_error("", 0, "case",
                          fmt::format("expected 10 numbers (ox oy oz dx dy dz cx cy cz r) or a corpus line "
                                      "(id family ox ... r [tmin tmax]), got {} fields",
                                      tokens.size()));
    }
    double v[10];
    for (int i = 0; i < 10; ++i) v[i] = parse_exact_double(tokens[first + i], "", 0, field_names[i]);
    c.geometry = {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
    if (tokens.size() == 14) {
        // '-' is an absent bound, as in a corpus file (and in the corpus line printed below).
        const auto bound = [&](const std::string& token, const char* field) -> std::optional<double> {
            if (token == "-") return std::nullopt;
            return parse_exact_double(token, "", 0, field);
        };
        c.tmin = bound(tokens[12], "tmin");
        c.tmax = bound(tokens[13], "tmax");
    }
    return c;
}

corpus_case case_from_corpus(const explain_options& options, const std::vector<corpus_case>& cases) {
    for (const corpus_case& c : cases)
        if (c.id == options.case_id) return c;
    throw input_error("", 0, "--case", fmt::format("no case with id '{}' in the corpus", options.case_id));
}

std::string root_text(double t, int sign) {
    const char* side = sign > 0 ? "t* > 0" : (sign == 0 ? "t* = 0" : "t* < 0");
    return fmt::format("{} ({}, {})", t, hex_float(t), side);
}

// The facts of the line, for any contract: the class, each root (correctly
// rounded) with its exact sign, and each root's point o + t·d. Which root a
// variant is asked for depends on its contract: each row below says.
void print_exact(const char* label, const exact_solution& e) {
    if (!e.valid()) {
        fmt::print("{}: invalid ({})\n", label, invalid_reason_name(e.invalid));
        return;
    }
    fmt::print("{}: {}\n", label, line_class_name(e.cls));
    if (e.cls == line_class::miss) return;
    for (root_index i : {root_index::near_root, root_index::far_root})
        fmt::print("    t_{} = {}, point ({}, {}, {})\n", i == root_index::near_root ? "near" : "far ",
                   root_text(e.root(i).rounded, e.root(i).sign), e.rounded_hit_coordinate(i, 0),
                   e.rounded_hit_coordinate(i, 1), e.rounded_hit_coordinate(i, 2));
}

// What a variant gave beside t (contract::outputs) and how it measured.
void print_outputs(const target_outcome& o) {
    const variant_output& out = o.output;
    const case_score& s = o.score;
    if (out.t_bounds)
        fmt::print("    t0 interval [{}, {}]{}\n", (*out.t_bounds)[0][0], (*out.t_bounds)[0][1],
                   s.bound_ulp ? fmt::format(", {} ulps wide", *s.bound_ulp) : std::string());
    if (out.hit_point) {
        const vec3<double>& p = *out.hit_point;
        fmt::print("    hit point ({}, {}, {})", p.x, p.y, p.z);
        if (out.point_error)
            fmt::print(" ± ({}, {}, {})", out.point_error->x, out.point_error->y, out.point_error->z);
        if (s.hit_point_ulp)
            fmt::print(", error ({}, {}, {}) ulp", format_figure((*s.hit_point_ulp)[0]),
                       format_figure((*s.hit_point_ulp)[1]), format_figure((*s.hit_point_ulp)[2]));
        fmt::print("\n");
    }
    if (out.normal)
        fmt::print("    normal ({}, {}, {}){}\n", out.normal->x, out.normal->y, out.normal->z,
                   s.normal_angle ? fmt::format(", {} rad from the exact normal", format_figure(*s.normal_angle)) : std::string());
    if (s.scale_error_radius)
        fmt::print("    |t − t*|·|d| = {} r = {} |o − c|\n", format_figure(*s.scale_error_radius),
                   format_figure(s.scale_error_distance));
}

std::string step_number(double x) {
    if (std::isnan(x)) return "nan";
    return fmt::format("{:.17g}", x);
}

// One traced step: computed, exact, relative error, bits lost, cancellation.
void print_step(const traced_step& s, exact_arithmetic& ideal) {
    const step_figures f = ideal.measure(s);
    const std::string lost = std::isnan(f.bits_lost) ? std::string("-")
                             : f.bits_lost >= s.digits ? fmt::format("all {}", s.digits)
                                                       : fmt::format("{:.1f} of {}", f.bits_lost, s.digits);
    const std::string cancelled = !s.subtraction            ? std::string("-")
                                  : std::isinf(s.cancelled) ? std::string("all")
                                                            : fmt::format("{:.1f}", s.cancelled);
    fmt::print("      {:<12} {:>24} {:>24} {:>10.3g} {:>10} {:>9}\n", s.name, step_number(s.computed),
               step_number(f.exact), f.relative_error, lost, cancelled);
    if (!s.note.empty()) fmt::print("      {:<12} ({})\n", "", s.note);
}

// Where the bits went: a built-in variant's own code run on traced scalars
// (intersectors/traced_variants.h), on the inputs and range the judge ran it on.
template <class T>
void print_trace(const variant_trace& trace, trace_fn<T> run, const audit_target& target, const corpus_case& c) {
    const std::optional<batch_case<T>> input = run_input<T>(target, c);
    if (!input || !run) return;
    exact_arithmetic ideal;
    trace_session session(ideal);
    run(input->input, input->interval.tmin, input->interval.tmax);
    fmt::print("    steps{}:\n", trace.what.empty() ? std::string() : fmt::format(" ({})", trace.what));
    fmt::print("      {:<12} {:>24} {:>24} {:>10} {:>10} {:>9}\n", "step", "computed", "exact", "rel. error",
               "bits lost", "cancelled");
    for (const traced_step& s : session.steps) print_step(s, ideal);
}

// The trace of a built-in target; nullptr for a plugin (even one that took a
// built-in's name), a results file, a program or an engine's library.
const variant_trace* builtin_trace(const audit_target& target) {
    const variant* builtin = find_builtin_variant(target.subject.name);
    const bool is_builtin = builtin && !target.recorded && !target.subject.library &&
                            builtin->citation == target.subject.citation && builtin->formula == target.subject.formula;
    return is_builtin ? find_builtin_trace(builtin->name) : nullptr;
}

// What can be derived for a target whose formula rayverify does not hold (a
// plugin, a results file, a program, an engine's library): the class its
// answer implies beside the exact one, and the scales that decide how many
// bits a quadratic's coefficients keep.
void print_derived(const target_outcome& o, const contract& promises, const exact_solution& exact,
                   const ray_sphere<double>& g) {
    if (!exact.valid()) return;
    const int count = o.output.roots.count;
    const char* exact_sign = exact.cls == line_class::miss ? "Δ′ < 0" : exact.cls == line_class::tangent ? "Δ′ = 0" : "Δ′ > 0";
    std::string implied;
    if (promises.query == query_kind::line_roots)
        implied = count == 0 ? "Δ′ < 0" : count == 1 ? "Δ′ = 0" : "Δ′ > 0";
    else
        implied = count == 0 ? "no root in its range (Δ′ < 0, or the roots outside it)" : "Δ′ ≥ 0 (a root in its range)";
    const vec3<double> f = g.origin - g.centre;
    const double distance = std::sqrt(length_squared(f)), length = std::sqrt(length_squared(g.direction));
    fmt::print("    derived (no formula to trace): the answer implies {}; exact {}\n", implied, exact_sign);
    const double scale_bits = 2 * std::log2(distance / g.radius);
    fmt::print("    scales: |o − c| = {:.3g} = 2^{:.1f} r, |d| = {:.3g}; a p-bit C = |o − c|² − r² keeps about p − {:.1f} "
               "bits of r²\n",
               distance, scale_bits / 2, length, scale_bits);
}

int run(const explain_options& options) {
    if (!options.case_id.empty() && !options.values.empty())
        throw input_error("", 0, "--case", "give either --case ID or the case's numbers, not both");
    if (options.case_id.empty() && options.values.empty())
        throw input_error("", 0, "case", "give the case as 10 numbers, a corpus line, or --case ID");
    if (!options.results.file.empty() && options.case_id.empty())
        throw input_error("", 0, "--results", "answers are found by case id: give --case ID (and its --corpus)");
    std::vector<corpus_case> corpus;
    if (!options.case_id.empty()) {
        std::vector<std::filesystem::path> paths(options.corpus.begin(), options.corpus.end());
        if (paths.empty()) paths.emplace_back(default_corpus());
        corpus = read_corpus(paths);  // to find one case by id: no summary of what was read
    }
    const corpus_case c = options.case_id.empty() ? case_from_arguments(options.values) : case_from_corpus(options, corpus);
    // A results file answers its corpus, found by id; a program is asked this one case.
    const std::vector<audit_target> outside = outside_targets(options.results, options.precisions, [&](const case_sink& add) {
        const std::span<const corpus_case> asked =
            options.results.file.empty() ? std::span<const corpus_case>(&c, 1) : std::span<const corpus_case>(corpus);
        for (const corpus_case& k : asked) add(k);
        return fingerprint_of(asked);
    });
    const std::vector<audit_target> targets =
        targets_with_results(options.variants, options.plugins, options.precisions, options.isolation, options.results,
                             outside);
    const audited_case audited = audit_case(c, targets);

    const auto& g = c.geometry;
    if (c.segment_end)
        fmt::print("case {}: segment p0 = ({}, {}, {})  p1 = ({}, {}, {})  c = ({}, {}, {})  r = {}  (t is the "
                   "fraction of p1 - p0, taken exactly)\n",
                   c.id, g.origin.x, g.origin.y, g.origin.z, c.segment_end->x, c.segment_end->y, c.segment_end->z,
                   g.centre.x, g.centre.y, g.centre.z, g.radius);
    else
        fmt::print("case {}: o = ({}, {}, {})  d = ({}, {}, {})  c = ({}, {}, {})  r = {}\n", c.id, g.origin.x,
                   g.origin.y, g.origin.z, g.direction.x, g.direction.y, g.direction.z, g.centre.x, g.centre.y,
                   g.centre.z, g.radius);
    fmt::print("corpus line: {}\n\n", format_case_line(c));
    print_exact("exact, double inputs", audited.exact_double);
    if (audited.exact_float) print_exact("exact, inputs rounded to float", *audited.exact_float);

    fmt::print("\n{:<26} {:<18} {:<20} {:>5} {:>24} {:>24} {:>10} {:>10}\n", "variant", "verdict", "cause", "count",
               "t0", "t1", "near_ulp", "far_ulp");
    bool findings = false;
    bool any_steps = false;
    std::vector<verdict_kind> seen;
    std::vector<disagreement_cause> causes;
    for (std::size_t i = 0; i < targets.size(); ++i) {
        const target_outcome& o = audited.outcomes[i];
        const contract& promises = targets[i].subject.promises;
        const auto& r = o.output.roots;
        const bool ran = is_scored(o.score.verdict);
        // Every value the judge looked at: a line answer's t1 even with count 1.
        const bool shows_t0 = ran && r.count > 0 && promises.query != query_kind::any_hit;
        const bool shows_t1 = shows_t0 && promises.query == query_kind::line_roots;
        fmt::print("{:<26} {:<18} {:<20} {:>5} {:>24} {:>24} {:>10} {:>10}\n", targets[i].label(),
                   verdict_name(o.score.verdict), o.score.cause ? cause_name(*o.score.cause) : "-",
                   ran ? std::to_string(r.count) : "-", shows_t0 ? fmt::format("{}", r.t0) : "-",
                   shows_t1 ? fmt::format("{}", r.t1) : "-", format_figure(o.score.near_ulp),
                   format_figure(o.score.far_ulp));
        if (ran) fmt::print("    contract: {}\n", describe_contract(promises));
        if (ran && !targets[i].subject.build.empty()) fmt::print("    build: {}\n", targets[i].subject.build);
        if (ran) print_outputs(o);
        if (ran && promises.query != query_kind::line_roots)
            fmt::print("    asks for: {}\n", describe_expected(promises, audited.exact_for(targets[i].prec), o.range));
        if (!o.score.detail.empty()) fmt::print("    {}\n", o.score.detail);
        if (ran && !options.no_steps) {
            const variant_trace* trace = builtin_trace(targets[i]);
            if (!trace)
                print_derived(o, promises, audited.exact_for(targets[i].prec), target_input(targets[i].prec, c));
            else if (targets[i].prec == precision::binary32)
                print_trace<float>(*trace, trace->in_float, targets[i], c);
            else
                print_trace<double>(*trace, trace->in_double, targets[i], c);
            any_steps = any_steps || trace;
        }
        findings = findings || is_disagreement(o.score.verdict);
        if (o.score.verdict != verdict_kind::agree &&
            std::find(seen.begin(), seen.end(), o.score.verdict) == seen.end())
            seen.push_back(o.score.verdict);
        if (o.score.cause && std::find(causes.begin(), causes.end(), *o.score.cause) == causes.end())
            causes.push_back(*o.score.cause);
    }
    if (!seen.empty()) fmt::print("\n");
    for (verdict_kind k : seen) fmt::print("{}: {}\n", verdict_name(k), verdict_meaning(k));
    for (disagreement_cause c : causes) fmt::print("cause {}: {}\n", cause_name(c), cause_meaning(c));
    if (any_steps)
        fmt::print("{}steps: each intermediate the variant's code names, computed in its precision (bit for bit as "
                   "it runs) and exact: the same expression on the same inputs in MPFR at {} bits (exact for + − × "
                   "and fma; √ and ÷ correctly rounded to that many bits); bits lost = p + log2(rel. error) of p = 24 "
                   "or 53, all when the computed value is 0 or of the wrong sign; cancelled: the bits a difference "
                   "x − y cancelled, log2(max(|x|, |y|)/|x − y|)\n",
                   seen.empty() && causes.empty() ? "\n" : "", exact_arithmetic::precision_bits);
    return findings ? exit_findings : exit_ok;
}

}  // namespace

command add_explain_command(CLI::App& app) {
    auto options = std::make_shared<explain_options>();
    auto* sub = app.add_subcommand(
        "explain", "One case, exact answer and every variant's answer side by side. Give the case as "
                   "'ox oy oz dx dy dz cx cy cz r' (decimal or C99 hex floats), as a corpus line, or --case ID");
    sub->add_option("case", options->values, "The case's numbers or corpus line");
    sub->add_option("--case", options->case_id, "Id of a case in --corpus");
    // Each repeatable option takes one value per use, so that the case after
    // it (`explain --plugin LIB "<corpus line>"`) stays the positional argument.
    sub->add_option("--corpus", options->corpus, "Corpus to look --case up in (default: the shipped corpus)")
        ->allow_extra_args(false);
    sub->add_option("--variant", options->variants, "Variant to show (repeatable; default: all)")
        ->allow_extra_args(false);
    sub->add_option("--plugin", options->plugins, "Shared library implementing rayverify_plugin.h (repeatable)")
        ->allow_extra_args(false);
    add_isolation_options(sub, options->isolation);
    add_results_options(sub, options->results);
    sub->add_flag("--no-steps", options->no_steps,
                  "Leave out each variant's intermediates (computed and exact, the bits lost at each step)");
    sub->add_option("--precision", options->precisions, "float or double (repeatable; default: both)")
        ->check(CLI::IsMember(precision_names()))
        ->allow_extra_args(false);
    // Negative numbers are values here, not options.
    sub->allow_extras(false);
    sub->positionals_at_end(false);
    return {sub, [options] { return run(*options); }};
}

}  // namespace rayverify::cli
