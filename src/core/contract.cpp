#include "core/contract.h"

#include <algorithm>
#include <array>
#include <deque>
#include <mutex>
#include <charconv>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/name_table.h"

namespace rayverify {
namespace {

// One table per enum (core/name_table.h).
constexpr name_table<query_kind, 3> query_kind_names{{
    {query_kind::line_roots, "line_roots"}, {query_kind::nearest_hit, "nearest_hit"}, {query_kind::any_hit, "any_hit"}}};
constexpr name_table<range_source, 4> range_source_names{{{range_source::ray, "ray"},
                                                          {range_source::interval, "interval"},
                                                          {range_source::tmax_only, "tmax_only"},
                                                          {range_source::segment, "segment"}}};
constexpr name_table<inside_rule, 3> inside_rule_names{
    {{inside_rule::far_root, "far_root"}, {inside_rule::clamp, "clamp"}, {inside_rule::miss, "miss"}}};
constexpr name_table<answer_kind, 2> answer_kind_names{{{answer_kind::t, "t"}, {answer_kind::point, "point"}}};
constexpr name_table<point_bound, 3> point_bound_names{
    {{point_bound::none, "no"}, {point_bound::hit, "yes"}, {point_bound::surface, "surface"}}};
constexpr name_table<accuracy_unit, 4> accuracy_unit_names{{{accuracy_unit::none, "none"},
                                                            {accuracy_unit::ulp, "ulp"},
                                                            {accuracy_unit::radius, "radius"},
                                                            {accuracy_unit::distance, "distance"}}};

// The shortest decimal that reads back as x (std::to_chars), ±inf spelled out.
std::string number_text(double x) {
    if (std::isinf(x)) return x > 0 ? "+inf" : "-inf";
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
    return std::string(buffer, end);
}

// The whole text as a double (std::from_chars), or nullopt; number_text's inverse.
std::optional<double> number_from_text(std::string_view text) {
    double x = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
    return x;
}

// "()", "[]", "[)", "(]": the ends as brackets.
std::string ends_text(end_kind lower, end_kind upper) {
    return std::string(lower == end_kind::closed ? "[" : "(") + (upper == end_kind::closed ? "]" : ")");
}

std::string_view yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::string_view interned_text(std::string text) {
    static std::mutex mutex;
    static std::deque<std::string> strings;
    const std::lock_guard lock(mutex);
    for (const std::string& s : strings)
        if (s == text) return s;
    return strings.emplace_back(std::move(text));
}

std::string_view query_kind_name(query_kind k) { return name_in(query_kind_names, k); }
std::string_view range_source_name(range_source r) { return name_in(range_source_names, r); }
std::string_view inside_rule_name(inside_rule i) { return name_in(inside_rule_names, i); }
std::string_view answer_kind_name(answer_kind a) { return name_in(answer_kind_names, a); }
std::string_view point_bound_name(point_bound b) { return name_in(point_bound_names, b); }

std::string_view accuracy_unit_name(accuracy_unit u) { return name_in(accuracy_unit_names, u); }

std::string format_accuracy(const accuracy_requirement& a) {
    if (!a.required()) return "none";
    return std::string(accuracy_unit_name(a.unit)) + ":" + number_text(a.bound);
}

accuracy_requirement parse_accuracy(std::string_view text) {
    const auto fail = [&](const std::string& why) {
        return std::invalid_argument("accuracy='" + std::string(text) + "': " + why +
                                     " (expected none, ulp:N, radius:X or distance:X with a finite bound >= 0)");
    };
    if (text == "none") return {};
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos) throw fail("no unit:bound");
    const std::string_view unit_text = text.substr(0, colon), bound_text = text.substr(colon + 1);
    const std::optional<accuracy_unit> unit = value_in(accuracy_unit_names, unit_text);
    if (!unit || *unit == accuracy_unit::none)
        throw fail("unknown unit '" + std::string(unit_text) + "' (units: ulp, radius, distance)");
    const std::optional<double> bound = number_from_text(bound_text);
    if (!bound) throw fail("the bound '" + std::string(bound_text) + "' is not a number");
    if (!std::isfinite(*bound)) throw fail("the bound is not finite");
    if (*bound < 0) throw fail("the bound is negative");
    return {*unit, *bound};
}

std::optional<query_kind> query_kind_from_name(std::string_view name) { return value_in(query_kind_names, name); }
std::optional<range_source> range_source_from_name(std::string_view name) {
    return value_in(range_source_names, name);
}
std::optional<inside_rule> inside_rule_from_name(std::string_view name) { return value_in(inside_rule_names, name); }
std::optional<answer_kind> answer_kind_from_name(std::string_view name) { return value_in(answer_kind_names, name); }
std::optional<point_bound> point_bound_from_name(std::string_view name) { return value_in(point_bound_names, name); }

std::string format_range(const t_range& r) {
    return (r.lower_end == end_kind::closed ? "[" : "(") + number_text(r.lower) + ", " + number_text(r.upper) +
           (r.upper_end == end_kind::closed ? "]" : ")");
}

std::string format_contract(const contract& c) {
    std::string spec = "query=" + std::string(query_kind_name(c.query)) + ",range=" +
                       std::string(range_source_name(c.range)) + ",ends=" + ends_text(c.lower_end, c.upper_end) +
                       ",inside=" + std::string(inside_rule_name(c.inside)) +
                       ",tangent=" + (c.tangent_is_hit ? "hit" : "miss") +
                       ",faces=" + (c.front_faces_only ? "front" : "both") +
                       ",unit_direction=" + std::string(yes_no(c.assumes_unit_direction));
    if (c.query == query_kind::line_roots) spec += ",reports_tangent=" + std::string(yes_no(c.reports_tangent));
    if (c.tangent_threshold) spec += ",tangent_threshold=" + number_text(*c.tangent_threshold);
    if (c.answer != answer_kind::t) spec += ",answer=" + std::string(answer_kind_name(c.answer));
    if (c.outputs.t_bounds) spec += ",t_bounds=yes";
    if (c.outputs.hit_point && c.answer == answer_kind::t) spec += ",hit_point=yes";
    if (c.outputs.point_error != point_bound::none)
        spec += ",point_error=" + std::string(point_bound_name(c.outputs.point_error));
    if (c.outputs.normal) spec += ",normal=yes";
    if (c.accuracy.required()) spec += ",accuracy=" + format_accuracy(c.accuracy);
    if (c.degenerate_is_miss) spec += ",degenerate=miss";
    if (c.takes_segment_ends) spec += ",cast=segment";
    return spec;
}

std::optional<std::string> contract_problem(const contract& c) {
    if (c.outputs.point_error != point_bound::none && !gives_hit_point(c))
        return "point_error needs a hit point (hit_point=yes)";
    if (c.query == query_kind::any_hit && (gives_hit_point(c) || c.outputs.normal || c.outputs.t_bounds))
        return "an any_hit contract returns no t, point or normal";
    if (c.answer == answer_kind::point && c.query != query_kind::nearest_hit)
        return "answer=point needs query=nearest_hit (one hit point)";
    if (c.answer == answer_kind::point && c.outputs.t_bounds) return "t_bounds needs answer=t";
    if (c.query == query_kind::any_hit && c.accuracy.required())
        return "accuracy needs a returned t: an any_hit contract returns none";
    if (c.takes_segment_ends && c.range != range_source::interval)
        return "cast=segment answers on the segment's fractions [0, 1], as range=interval passes them: give range=interval";
    if (c.takes_segment_ends && c.assumes_unit_direction)
        return "cast=segment takes end points: a unit direction cannot be assumed (unit_direction=no)";
    return std::nullopt;
}

std::string describe_contract(const contract& c) {
    const std::string open = c.lower_end == end_kind::closed ? "[" : "(";
    const std::string close = c.upper_end == end_kind::closed ? "]" : ")";
    std::string range;
    switch (c.range) {
        case range_source::ray: range = format_range(range_of(c, std::nullopt, std::nullopt)); break;
        case range_source::interval: range = open + "tmin, tmax" + close; break;
        case range_source::tmax_only: range = open + "0, tmax" + close + " (no tmin)"; break;
        case range_source::segment: range = "the segment " + open + "o + tmin·d, o + tmax·d" + close; break;
    }
    std::string out;
    switch (c.query) {
        case query_kind::line_roots:
            out = "both roots of the line, any sign; in front means t in " + range;
            out += c.reports_tangent ? "; reports a tangent when " + std::string(c.tangent_rule)
                                     : std::string("; never reports a tangent");
            break;
        case query_kind::nearest_hit:
        case query_kind::any_hit:
            out = std::string(c.query == query_kind::nearest_hit ? "nearest hit" : "any hit") + " in " + range +
                  "; starting inside: " +
                  (c.inside == inside_rule::far_root ? "the far root"
                   : c.inside == inside_rule::clamp  ? "clamped to the range start"
                                                     : "a miss") +
                  "; a tangent is a " + (c.tangent_is_hit ? "hit" : "miss") + "; " +
                  (c.front_faces_only ? "front faces only" : "both faces");
            break;
    }
    if (c.tangent_threshold) out += " (tangent whenever b′² − aC ≤ " + number_text(*c.tangent_threshold) + ")";
    if (c.assumes_unit_direction) out += "; assumes |d| = 1";
    if (c.answer == answer_kind::point) out += "; answers with the hit point (t derived from it)";
    std::string outputs;
    const auto add = [&](bool given, const char* what) {
        if (given) outputs += (outputs.empty() ? "" : ", ") + std::string(what);
    };
    add(c.outputs.t_bounds, "an interval for each t");
    add(c.outputs.hit_point && c.answer == answer_kind::t, "the hit point");
    add(c.outputs.point_error == point_bound::hit, "an error bound per coordinate of the hit point");
    add(c.outputs.point_error == point_bound::surface,
        "an error bound per coordinate of the hit point that holds a point of the sphere");
    add(c.outputs.normal, "the normal");
    if (!outputs.empty()) out += "; also gives " + outputs;
    switch (c.accuracy.unit) {
        case accuracy_unit::none: break;
        case accuracy_unit::ulp: out += "; required: t within " + number_text(c.accuracy.bound) + " ulp of t*"; break;
        case accuracy_unit::radius:
            out += "; required: |t - t*|·|d| within " + number_text(c.accuracy.bound) + " r";
            break;
        case accuracy_unit::distance:
            out += "; required: |t - t*|·|d| within " + number_text(c.accuracy.bound);
            break;
    }
    if (c.degenerate_is_miss) out += "; a degenerate cast (zero direction, non-finite input, empty interval) is a miss";
    if (c.takes_segment_ends) out += "; takes a segment's end points p0, p1 and answers the fraction along p1 - p0";
    return out;
}

contract parse_contract(std::string_view spec, contract c) {
    const auto fail = [&](std::string_view key, std::string_view value, const std::string& expected) {
        return std::invalid_argument("contract: " + std::string(key) + "='" + std::string(value) + "': expected " +
                                     expected);
    };
    const auto yes_no_value = [&](std::string_view key, std::string_view value) {
        if (value == "yes") return true;
        if (value == "no") return false;
        throw fail(key, value, "yes or no");
    };
    std::vector<std::string_view> given;  // the keys so far
    while (!spec.empty()) {
        const std::size_t comma = spec.find(',');
        const std::string_view item = spec.substr(0, comma);
        spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
        const std::size_t equals = item.find('=');
        if (item.empty() || equals == std::string_view::npos)
            throw std::invalid_argument("contract: '" + std::string(item) + "' is not key=value");
        const std::string_view key = item.substr(0, equals), value = item.substr(equals + 1);
        // One value per key: "query=line_roots,query=any_hit" says two things, and neither wins.
        if (std::find(given.begin(), given.end(), key) != given.end())
            throw std::invalid_argument("contract: '" + std::string(key) + "' is given twice");
        given.push_back(key);
        if (key == "query") {
            const auto v = query_kind_from_name(value);
            if (!v) throw fail(key, value, allowed_names(query_kind_names));
            c.query = *v;
        } else if (key == "range") {
            const auto v = range_source_from_name(value);
            if (!v) throw fail(key, value, allowed_names(range_source_names));
            c.range = *v;
        } else if (key == "ends") {
            if (value.size() != 2 || (value[0] != '(' && value[0] != '[') || (value[1] != ')' && value[1] != ']'))
                throw fail(key, value, "(), [], [) or (]");
            c.lower_end = value[0] == '[' ? end_kind::closed : end_kind::open;
            c.upper_end = value[1] == ']' ? end_kind::closed : end_kind::open;
        } else if (key == "inside") {
            const auto v = inside_rule_from_name(value);
            if (!v) throw fail(key, value, allowed_names(inside_rule_names));
            c.inside = *v;
        } else if (key == "tangent") {
            if (value != "hit" && value != "miss") throw fail(key, value, "hit or miss");
            c.tangent_is_hit = value == "hit";
        } else if (key == "faces") {
            if (value != "both" && value != "front") throw fail(key, value, "both or front");
            c.front_faces_only = value == "front";
        } else if (key == "unit_direction") {
            c.assumes_unit_direction = yes_no_value(key, value);
        } else if (key == "reports_tangent") {
            c.reports_tangent = yes_no_value(key, value);
        } else if (key == "tangent_threshold") {
            const std::optional<double> x = number_from_text(value);
            if (!x || !std::isfinite(*x) || *x < 0) throw fail(key, value, "a finite number ≥ 0");
            c.tangent_threshold = *x;
        } else if (key == "answer") {
            const auto v = answer_kind_from_name(value);
            if (!v) throw fail(key, value, allowed_names(answer_kind_names));
            c.answer = *v;
        } else if (key == "t_bounds") {
            c.outputs.t_bounds = yes_no_value(key, value);
        } else if (key == "hit_point") {
            c.outputs.hit_point = yes_no_value(key, value);
        } else if (key == "point_error") {
            const auto v = point_bound_from_name(value);
            if (!v) throw fail(key, value, allowed_names(point_bound_names));
            c.outputs.point_error = *v;
        } else if (key == "normal") {
            c.outputs.normal = yes_no_value(key, value);
        } else if (key == "degenerate") {
            if (value != "miss" && value != "invalid") throw fail(key, value, "miss or invalid");
            c.degenerate_is_miss = value == "miss";
        } else if (key == "cast") {
            if (value != "ray" && value != "segment") throw fail(key, value, "ray or segment");
            c.takes_segment_ends = value == "segment";
        } else if (key == "accuracy") {
            try {
                c.accuracy = parse_accuracy(value);
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument("contract: " + std::string(e.what()));
            }
        } else {
            throw std::invalid_argument("contract: unknown key '" + std::string(key) +
                                        "' (keys: query, range, ends, inside, tangent, faces, unit_direction, "
                                        "reports_tangent, tangent_threshold, answer, t_bounds, hit_point, "
                                        "point_error, normal, accuracy, degenerate, cast)");
        }
    }
    if (auto problem = contract_problem(c)) throw std::invalid_argument("contract: " + *problem);
    return c;
}

}  // namespace rayverify
