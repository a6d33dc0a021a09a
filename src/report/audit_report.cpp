#include "report/audit_report.h"

#include "compare/error_figures.h"
#include "report/stability_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

#include "core/build_info.h"
#include "corpus/corpus_io.h"
#include "report/schema.h"

namespace rayverify {

using json = nlohmann::ordered_json;

void write_number(json_line& out, double x) {
    if (std::isnan(x))
        out.value("nan");
    else if (std::isinf(x))
        out.value(x > 0 ? "inf" : "-inf");
    else
        out.value(x);
}

namespace {

// The figures' names on a case's line (error_figures' case_name), checked
// when compiled to need no escaping, so that each line copies them as they are.
constexpr std::array<json_name, error_figure_count> figure_case_names =
    []<std::size_t... figure>(std::index_sequence<figure...>) {
        return std::array<json_name, error_figure_count>{json_name(error_figures[figure].case_name)...};
    }(std::make_index_sequence<error_figure_count>{});

// A figure as printed (printed_figure), spelled from its decimal digits
// where arithmetic finds them, else from the printed double: the same text
// either way (json_decimal_text).
void write_figure(json_line& out, double x) {
    if (printed_decimal d; printed_figure_decimal(x, d))
        out.decimal(d.negative, d.digits, d.exponent);
    else
        write_number(out, printed_figure(x));
}

}  // namespace

json build_json() {
    return {{"rayverify_version", build_info::version},
            {"compiler", build_info::compiler},
            {"build_type", build_info::build_type},
            {"flags", build_info::flags}};
}

std::string build_summary() {
    return fmt::format("{} {} [{}]", build_info::compiler, build_info::flags, build_info::build_type);
}

std::size_t verdict_column_width(std::string_view heading) { return std::max<std::size_t>(6, heading.size()); }

const std::string quantile_scope =
    "upper bounds: the nearest-rank value's log bucket upper edge (at most a factor 1 + 2^-7 above it) "
    "or the maximum when smaller, then printed rounded like every figure; exact when 0";

namespace {

json statistics_json(const error_statistics& s, const char* scope) {
    json out = {{"count", s.count}};
    if (s.count == 0) return out;
    out["max"] = json_number(printed_figure(s.max));
    out["p99"] = json_number(printed_figure(s.p99));
    out["median"] = json_number(printed_figure(s.median));
    out["max_case"] = s.max_case;
    out["max_is"] = scope;
    out["p99_median_are"] = quantile_scope;
    return out;
}

json tally_json(const target_tally& t, const char* scope) {
    json verdicts = json::object();
    for (int k = 0; k < verdict_kind_count; ++k)
        verdicts[std::string(verdict_name(static_cast<verdict_kind>(k)))] = t.verdicts[k];
    json causes = json::object();
    for (int c = 0; c < disagreement_cause_count; ++c)
        causes[std::string(cause_name(static_cast<disagreement_cause>(c)))] = t.causes[c];
    json out = {{"cases", t.cases}, {"disagreements", t.disagreements()}, {"verdicts", verdicts}, {"causes", causes}};
    for (const error_figure_definition& f : error_figures)
        out[std::string(f.name)] = statistics_json(t.errors[f.figure], scope);
    out["agree_far"] = t.agree_far;
    return out;
}


}  // namespace

void map_json(json_io& io, precision& p) {
    io.name(p, precision_name, precision_from_name, "float or double");
}

void map_json(json_io& io, verdict_kind& v) { io.name(v, verdict_name, verdict_from_name, "a verdict"); }
void map_json(json_io& io, disagreement_cause& c) { io.name(c, cause_name, cause_from_name, "a cause"); }

void map_json(json_io& io, invalid_reason& r) {
    io.name(r, invalid_reason_name,
            [](std::string_view name) -> std::optional<invalid_reason> {
                for (int k = 0; k <= static_cast<int>(invalid_reason::bad_interval); ++k)
                    if (name == invalid_reason_name(static_cast<invalid_reason>(k))) return static_cast<invalid_reason>(k);
                return std::nullopt;
            },
            "a reason a case is invalid");
}

void map_json(json_io& io, library_identity& library) {
    io.field("name", library.name);
    io.field("version", library.version);
    io.field("source", library.source);
    std::optional<std::string> configuration;
    if (!library.configuration.empty()) configuration = library.configuration;
    io.optional_field("configuration", configuration);
    if (io.reading()) library.configuration = configuration.value_or("");
}

void map_json(json_io& io, contract& c) {
    std::string spec = io.reading() ? "" : format_contract(c);
    std::string tangent_rule(c.tangent_rule), meaning = io.reading() ? "" : describe_contract(c);
    io.field("spec", spec);
    if (io.reading()) {
        try {
            c = parse_contract(spec);
        } catch (const std::invalid_argument& e) {
            io.fail("spec", fmt::format("{}: {}", json_io::quoted(spec), e.what()));
        }
    }
    io.field("tangent_rule", tangent_rule);
    io.field("meaning", meaning);
    if (io.reading()) c.tangent_rule = interned_text(tangent_rule);
}

void map_json(json_io& io, audit_target& target) {
    io.field("variant", target.subject.name);
    io.field("precision", target.prec);
    io.field("citation", target.subject.citation);
    io.field("formula", target.subject.formula);
    io.field("contract", target.subject.promises);
    io.optional_field("library", target.subject.library);
    std::optional<std::string> environment;
    if (!target.subject.fp_environment.empty()) environment = target.subject.fp_environment;
    io.optional_field("fp_environment", environment);
    if (io.reading()) target.subject.fp_environment = environment.value_or("");
}

namespace {

void write_exact(json_line& out, const exact_solution& e) {
    out.begin_object();
    if (!e.valid()) {
        out.member("invalid", invalid_reason_name(e.invalid)).end_object();
        return;
    }
    out.member("class", line_class_name(e.cls));
    if (e.cls != line_class::miss) {
        out.key("t_near").hex(e.near_root.rounded);
        out.key("t_far").hex(e.far_root.rounded);
        out.member("near_sign", e.near_root.sign);
        out.member("far_sign", e.far_root.sign);
        // Facts of the line, for any contract: each root's point o + t·d,
        // correctly rounded (which root is "the hit" is each result's "expected").
        out.key("hit_points").begin_object();
        for (root_index i : {root_index::near_root, root_index::far_root}) {
            out.key(i == root_index::near_root ? json_name("near") : json_name("far")).begin_array();
            for (int axis = 0; axis < 3; ++axis) out.hex(e.rounded_hit_coordinate(i, axis));
            out.end_array();
        }
        out.end_object();
    }
    out.end_object();
}

// What a nearest_hit or any_hit contract asks for on this case.
void write_expected(json_line& out, const contract& promises, const exact_solution& exact, const t_range& range) {
    out.begin_object();
    const expected_hit want = exact.cls == line_class::miss ? expected_hit{} : expect_hit(promises, exact, range);
    switch (want.what) {
        case expected_hit::kind::none: out.member("answer", "none"); break;
        case expected_hit::kind::clamp: out.member("answer", "clamp").key("t").hex(want.value); break;
        case expected_hit::kind::root:
            out.member("answer", want.root == root_index::near_root ? "near" : "far").key("t").hex(want.value);
            break;
    }
    out.end_object();
}

// "zero_direction", or "float: not_representable_in_precision" when only float
// finds it invalid. A case invalid in double is invalid in float too, unless float did not run.
std::string invalid_reasons_text(const invalid_case& c) {
    if (c.at_float == c.at_double || c.at_float == invalid_reason::none) return invalid_reason_name(c.at_double);
    std::string text;
    for (const auto& [name, reason] : {std::pair{"float", c.at_float}, std::pair{"double", c.at_double}})
        if (reason != invalid_reason::none)
            text += fmt::format("{}{}: {}", text.empty() ? "" : "; ", name, invalid_reason_name(reason));
    return text;
}

}  // namespace

namespace {

// The counts of a "verdicts" object whose verdict `holds`.
std::size_t counted_where(const json& verdicts, bool (*holds)(verdict_kind)) {
    std::size_t n = 0;
    for (const auto& [name, count] : verdicts.items())
        if (const auto kind = verdict_from_name(name); kind && holds(*kind)) n += count.get<std::size_t>();
    return n;
}

}  // namespace

std::size_t scored_in(const json& verdicts) { return counted_where(verdicts, is_scored); }
std::size_t misclassified_in(const json& verdicts) { return counted_where(verdicts, is_misclassification); }

// The summary table's "far" column (agree but far, compare/audit.h), beside agree.
constexpr int agree_far_column_width = 5;

std::string render_summary_table(const audit_totals& totals) {
    std::string out;
    std::size_t name_width = 7;
    for (const auto& t : totals.targets) name_width = std::max(name_width, t.subject.name.size());
    out += fmt::format("{:<{}} {:<6} {:>6}", "variant", name_width, "prec", "cases");
    for (int k = 0; k < verdict_kind_count; ++k) {
        const auto kind = static_cast<verdict_kind>(k);
        if (is_corpus_verdict(kind)) out += fmt::format(" {:>{}}", verdict_column(kind), verdict_column_width(verdict_column(kind)));
        if (kind == verdict_kind::agree) out += fmt::format(" {:>{}}", "far", agree_far_column_width);
    }
    out += fmt::format(" {:>6} {:>9} {:>9} {:>9}\n", "design", "max_ulp", "p99_ulp", "med_ulp");
    for (std::size_t i = 0; i < totals.targets.size(); ++i) {
        const audit_target& target = totals.targets[i];
        const target_tally& t = totals.overall[i];
        out += fmt::format("{:<{}} {:<6} {:>6}", target.subject.name, name_width, precision_name(target.prec), t.cases);
        for (int k = 0; k < verdict_kind_count; ++k) {
            const auto kind = static_cast<verdict_kind>(k);
            if (is_corpus_verdict(kind)) out += fmt::format(" {:>{}}", t.verdicts[k], verdict_column_width(verdict_column(kind)));
            if (kind == verdict_kind::agree) out += fmt::format(" {:>{}}", t.agree_far, agree_far_column_width);
        }
        out += fmt::format(" {:>6}", t.by_design());
        const error_statistics& s = t.errors[error_figure::near_root_ulp];
        if (s.count == 0)
            out += fmt::format(" {:>9} {:>9} {:>9}\n", "-", "-", "-");
        else
            out += fmt::format(" {:>9} {:>9} {:>9}\n", format_figure(s.max), format_figure(s.p99), format_figure(s.median));
    }
    out += fmt::format("{} cases; invalid: {} at float, {} at double. far: agreeing cases whose t lies far from t* "
                       "along the ray ({}; --accuracy makes an answer beyond a bound you choose imprecise). ULP "
                       "columns: nearest root, agreeing cases, maxima over this finite corpus; p99 and median are "
                       "upper bounds within 0.8%; every figure to {} significant digits.\n",
                       totals.cases, totals.invalid_cases[0], totals.invalid_cases[1], agree_far_rule,
                       figure_significant_digits);
    // Invalid cases are never scored, so they are named: the first few here, all in report.json.
    constexpr std::size_t listed = 5;
    if (!totals.invalid_list.empty()) {
        const bool handed_over = std::any_of(totals.targets.begin(), totals.targets.end(), [](const audit_target& t) {
            return t.subject.promises.degenerate_is_miss;
        });
        out += fmt::format("invalid cases ({}, {}):", totals.invalid_list.size(),
                           handed_over ? "no exact answer; degenerate casts scored under degenerate=miss"
                                       : "not scored");
        for (std::size_t i = 0; i < std::min(listed, totals.invalid_list.size()); ++i)
            out += fmt::format("{} {} ({})", i ? "," : "", totals.invalid_list[i].id,
                               invalid_reasons_text(totals.invalid_list[i]));
        if (totals.invalid_list.size() > listed)
            out += fmt::format(", and {} more (all listed in report.json)", totals.invalid_list.size() - listed);
        out += "\n";
    }
    return out;
}

json audit_report_json(const audit_totals& totals, const run_context& context) {
    constexpr const char* scope = "maximum over this finite corpus";
    // Room for every member an audit's report gets, the eight below, the
    // four sections audit_report_document adds and the plots' note that
    // report_bundle adds, so that adding a section copies none before it.
    json report = json::object();
    reserve_members(report, 16);
    report["schema_version"] = schema_version::report;
    report["tool"] = "rayverify audit";
    report["build"] = build_json();
    report["command"] = context.command_line;
    report["corpus"] = {{"paths", context.corpus_paths},
                        {"cases", totals.cases},
                        {"cases_by_family", totals.cases_by_family},
                        {"invalid_cases", {{"float", totals.invalid_cases[0]}, {"double", totals.invalid_cases[1]}}}};
    if (!context.generated.empty()) report["corpus"]["generated"] = context.generated;
    json invalid_list = json::array();
    for (const invalid_case& c : totals.invalid_list) {
        json entry = {{"id", c.id}, {"source", c.source}};
        if (c.at_float != invalid_reason::none) entry["float"] = invalid_reason_name(c.at_float);
        if (c.at_double != invalid_reason::none) entry["double"] = invalid_reason_name(c.at_double);
        invalid_list.push_back(std::move(entry));
    }
    report["corpus"]["invalid_case_list"] = std::move(invalid_list);
    report["definitions"] = {
        {"ulp", "for 2^e <= |x| < 2^(e+1): ulp(x) = 2^(max(e, emin) - p + 1); p = 24, emin = -126 (float); "
                "p = 53, emin = -1022 (double); ulp(0) = smallest subnormal"},
        {"ulp_error", "|t - t*| / ulp(t*), t* the exact root of the inputs the variant received"},
        {"near_root_scaled_ulp", "ulp_error of the near root, except that where t* is exactly 0 (whose ulp is the "
                                 "smallest subnormal) it is |t| / ulp(r / |d|), the error in ulps of the radius "
                                 "measured along the ray: the scale the formula works at"},
        {"bits", "log2(1 + number of representable values between t and RN(t*))"},
        {"scale_error_radius", "max over the returned roots of |t - t*|·|d| / r: the error in units of the radius"},
        {"agree_far", "agreeing cases whose scale_error_radius is at least 2^-10 (about 0.1% of the radius): the "
                      "verdict only asks which root a t stands for, so a t this far off can still agree (unless "
                      "the contract's accuracy clause, audit --accuracy, makes it imprecise)"},
        {"scale_error_distance", "max over the returned roots of |t - t*|·|d| / |o - c|"},
        {"bound_width_ulp",
         "the widest interval a variant claims for a returned t, in representable values between its ends"},
        {"normal_angle", "angle in radians between the returned normal and the exact one (the nearer of ±n*)"},
        {"printed_figures", figure_printing_rule()},
        {"error_statistics",
         "over the cases whose verdict is agree; count and max are exact (max_case: the first case attaining it); "
         "p99 and median are nearest-rank, reported as upper bounds from a histogram of log buckets of relative "
         "width 2^-7 (the bucket's upper edge, or the max when it is smaller; 0 exactly when 0), so that the "
         "figures of any split of the cases merge exactly"}};
    json meanings = json::object();
    for (int k = 0; k < verdict_kind_count; ++k) {
        const auto kind = static_cast<verdict_kind>(k);
        meanings[std::string(verdict_name(kind))] = std::string(verdict_meaning(kind));
    }
    report["verdicts"] = std::move(meanings);

    json results = json::array();
    for (std::size_t i = 0; i < totals.targets.size(); ++i) {
        const audit_target& target = totals.targets[i];
        json entry = to_json_mapped(target);
        entry.update(tally_json(totals.overall[i], scope));
        json families = json::object();
        for (const auto& [family, tallies] : totals.by_family) families[family] = tally_json(tallies[i], scope);
        entry["by_family"] = std::move(families);
        results.push_back(std::move(entry));
    }
    report["results"] = std::move(results);
    return report;
}

std::string per_case_line(const audited_case& audited, const std::vector<audit_target>& targets,
                          std::string buffer) {
    const corpus_case& c = *audited.source;
    const auto& g = c.geometry;
    // Lines run to about 400 bytes per target plus the case's own fields: room
    // for 512 per target and 1 KB more is allocated once and reused, and made
    // ready for the previous line's length and a quarter more where `buffer`
    // holds one (json_line grows it where a line is longer).
    const std::size_t expected_size =
        buffer.empty() ? 1024 + 512 * targets.size() : buffer.size() + buffer.size() / 4 + 256;
    json_line line(std::move(buffer), expected_size);
    line.begin_object();
    line.member("schema_version", schema_version::per_case);
    line.member("id", c.id);
    if (!c.family.empty()) line.member("family", c.family);
    line.member("source", c.source);
    const auto hex_all = [&](const auto& values) {
        line.begin_array();
        for (double v : values) line.hex(v);
        line.end_array();
    };
    const auto hex_vec = [&](const vec3<double>& v) { hex_all(std::array<double, 3>{v.x, v.y, v.z}); };
    line.key("input").begin_object();
    line.key("o");
    hex_vec(g.origin);
    line.key("d");
    hex_vec(g.direction);
    if (c.segment_end) {  // a segment case: o is p0, d is p1 − p0 rounded to double
        line.key("p1");
        hex_vec(*c.segment_end);
    }
    line.key("c");
    hex_vec(g.centre);
    line.key("r").hex(g.radius).end_object();
    line.key("exact");
    write_exact(line, audited.exact_double);
    if (audited.exact_float) {
        line.key("exact_float");
        write_exact(line, *audited.exact_float);
    }

    line.key("results").begin_object();
    t_range shown_range;
    std::optional<std::string> range_text;
    const auto same_range = [](const t_range& a, const t_range& b) {
        return std::bit_cast<std::uint64_t>(a.lower) == std::bit_cast<std::uint64_t>(b.lower) &&
               std::bit_cast<std::uint64_t>(a.upper) == std::bit_cast<std::uint64_t>(b.upper) &&
               a.lower_end == b.lower_end && a.upper_end == b.upper_end;
    };
    for (std::size_t i = 0; i < targets.size(); ++i) {
        const target_outcome& o = audited.outcomes[i];
        const std::array<std::string_view, 3> label = targets[i].label_parts();
        line.key_text(label).begin_object();
        line.member("verdict", verdict_name(o.score.verdict));
        const bool ran = is_scored(o.score.verdict);
        if (o.score.cause) line.member("cause", cause_name(*o.score.cause));
        if (ran) {
            const contract& promises = targets[i].subject.promises;
            const exact_solution& exact = audited.exact_for(targets[i].prec);
            // Targets of a case mostly share one range: its text is formed once.
            if (!range_text || !same_range(o.range, shown_range)) {
                shown_range = o.range;
                range_text = format_range(o.range);
            }
            line.member("range", *range_text);
            if (promises.query != query_kind::line_roots) {
                line.key("expected");
                write_expected(line, promises, exact, o.range);
            }
            // Every value the judge looked at: both roots of a line answer (a
            // count-1 tangent's t1 included), the one root of a nearest hit.
            line.member("count", o.output.roots.count);
            if (o.output.roots.count > 0 && promises.query != query_kind::any_hit) {
                line.key("t0").hex(o.output.roots.t0);
                if (promises.query == query_kind::line_roots) line.key("t1").hex(o.output.roots.t1);
            }
            // The outputs beside t, as given (judged: bound_width_ulp, normal_angle, unsound_bound).
            if (o.output.t_bounds) {
                line.key("t0_bounds");
                hex_all((*o.output.t_bounds)[0]);
                line.key("t1_bounds");
                hex_all((*o.output.t_bounds)[1]);
            }
            if (o.output.point_error) {
                line.key("point_error");
                hex_vec(*o.output.point_error);
            }
            if (o.output.normal) {
                line.key("normal");
                hex_vec(*o.output.normal);
            }
        }
        const auto figure = [&](json_name name, const std::optional<double>& x) {
            if (!x) return;
            line.key(name);
            write_figure(line, *x);
        };
        // Figures the audit kept to their bucket print from their exact
        // values where their bounds print apart (printed_as_exact).
        const case_score& figures = printed_as_exact(o.score) ? o.score : audited.every_digit(i, targets[i]);
        for (const error_figure_definition& f : error_figures) {
            const json_name name = figure_case_names[static_cast<std::size_t>(f.figure)];
            if (f.figure == error_figure::hit_point_ulp) {
                // Per coordinate on a case's line (the tally keeps the worst).
                if (!figures.hit_point_ulp) continue;
                line.key(name).begin_array();
                for (const double e : *figures.hit_point_ulp) write_figure(line, e);
                line.end_array();
                continue;
            }
            figure(name, f.of_case(figures));
        }
        if (!o.score.detail.empty()) line.member("detail", o.score.detail);
        line.end_object();
    }
    line.end_object();
    line.key("stability");
    write_stability_measures(line, audited.stability);
    line.end_object();
    return line.take();
}

}  // namespace rayverify
