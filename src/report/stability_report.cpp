#include "report/stability_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "compare/error_figures.h"
#include "core/hash.h"
#include "report/audit_report.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

constexpr const char* scope = "maximum over this finite corpus";

json bucket_json(const bucket_tally& b) {
    json out = {{"cases", b.cases},
                {"misclassified", b.misclassified},
                {"misclassification_rate", b.cases ? static_cast<double>(b.misclassified) / b.cases : 0.0},
                {"disagreements", b.disagreements},
                {"conditioning_limited", b.conditioning_limited},
                {"algorithmic", b.algorithmic},
                {"by_design", b.by_design}};
    json ulp = {{"count", b.near_root_ulp.count}};
    if (b.near_root_ulp.count) {
        ulp["max"] = json_number(printed_figure(b.near_root_ulp.max));
        ulp["p99"] = json_number(printed_figure(b.near_root_ulp.p99));
        ulp["median"] = json_number(printed_figure(b.near_root_ulp.median));
        ulp["max_case"] = b.near_root_ulp.max_case;
        ulp["max_is"] = scope;
        ulp["p99_median_are"] = quantile_scope;
    }
    out["near_root_ulp"] = std::move(ulp);
    return out;
}

json tally_json(const stability_tally& t) {
    json buckets = json::array();
    for (int b = 0; b < condition_bucket_count; ++b) {
        if (t.buckets[b].cases == 0) continue;
        json entry = {{"condition", condition_bucket_label(b)}};
        entry.update(bucket_json(t.buckets[b]));
        buckets.push_back(std::move(entry));
    }
    json line = {{"judged", t.judged},
                 {"above_line", t.above_line},
                 {"well_conditioned", t.well_conditioned},
                 {"well_conditioned_above_line", t.well_conditioned_above},
                 {"stable", t.stable()}};
    if (t.excess.count) {
        line["max_excess"] = json_number(printed_figure(t.excess.max));
        line["p99_excess"] = json_number(printed_figure(t.excess.p99));
        line["median_excess"] = json_number(printed_figure(t.excess.median));
        line["max_excess_case"] = t.excess.max_case;
        line["max_is"] = scope;
        line["p99_median_are"] = quantile_scope;
    }
    json out = bucket_json(t.all);
    out["reference_line"] = std::move(line);
    out["buckets"] = std::move(buckets);
    return out;
}

std::string precision_label(const std::vector<std::string>& labels, const std::vector<audit_target>& targets,
                            std::size_t i) {
    return i < labels.size() ? labels[i] : precision_name(targets[i].prec);
}

}  // namespace

json stability_json(const audit_totals& totals, const stability_totals& stability,
                    const std::vector<std::string>& precision_labels) {
    json out;
    out["definitions"] = {
        {"condition",
         "kappa of the near root for relative perturbations of the 10 inputs: "
         "(sum_k |p_k|(|o_k| + |c_k| + |t||d_k|) + r^2) / (sqrt(D') |t|), p = o - c + t d, D' = b'^2 - aC = a r^2 - |d x f|^2 (evaluated in the second form); "
         "inf for a double root (tangent) or t = 0; none for a miss"},
        {"tangency_distance", "|D'| / (b'^2 + |a C|)"},
        {"tangency_margin",
         "|D'| / (u M), M = sum_i |dD'/dx_i| |x_i| = 2(sum_k |b'd_k - a f_k|(|o_k|+|c_k|) + sum_k |b'f_k - C d_k||d_k| + "
         "a r^2), u = 2^-24 (float) or 2^-53 (double)"},
        {"conditioning_limited",
         "a wrong class with tangency_margin <= 8 (relative input perturbations of 8u, the backward error of a "
         "stable evaluation, can flip the sign of D'); a wrong root, side or sphere with margin <= 8 or "
         "8 u kappa >= 1; either when a root lies within 8 u kappa |t| of a finite end of the range (a root "
         "exactly at 0 on a ray from 0, a self-hit, whichever root it is); non-finite and malformed outputs are "
         "always algorithmic"},
        {"by_design",
         "disagreements the formula makes by design, decided exactly: clamp, contract_semantics, unit_direction, "
         "tangent_threshold, line_not_ray (see the verdict causes)"},
        {"reference_line",
         "a backward-stable algorithm's near-root error is about kappa ulps or less (relative error kappa u); "
         "excess = near-root ulps / max(kappa, 1) over agreeing cases with finite kappa, and |t| / (u kappa |t|) "
         "at a root exactly 0 (kappa |t| is finite there; the larger where both apply); above_line counts excess > 16; "
         "stable = no case above the line; well_conditioned = kappa < 1e3"},
        {"buckets", "cases by decade of kappa; 'inf' = tangent or zero root, 'miss' = no real root"}};
    json results = json::array();
    for (std::size_t i = 0; i < totals.targets.size(); ++i) {
        json entry = {{"variant", totals.targets[i].subject.name},
                      {"precision", precision_label(precision_labels, totals.targets, i)}};
        entry.update(tally_json(stability.overall[i]));
        json families = json::object();
        for (const auto& [family, tallies] : stability.by_family) families[family] = tally_json(tallies[i]);
        entry["by_family"] = std::move(families);
        results.push_back(std::move(entry));
    }
    out["results"] = std::move(results);
    return out;
}

void write_stability_measures(json_line& out, const case_stability& s) {
    out.begin_object();
    for (const auto& [name, measures] : {std::pair{json_name("float"), &s.at_float}, std::pair{json_name("double"), &s.at_double}}) {
        if (!*measures) continue;
        const stability_measures& m = **measures;
        out.key(name).begin_object();
        if (!m.valid) {
            out.member("invalid", true).end_object();
            continue;
        }
        const auto optional = [&](const std::optional<double>& x) {
            if (x) write_number(out, *x);
            else out.null();
        };
        out.key("near_condition");
        optional(m.near_condition);
        out.key("far_condition");
        optional(m.far_condition);
        out.member("condition_bucket", condition_bucket_label(condition_bucket(m)));
        out.key("tangency_distance");
        write_number(out, m.tangency_distance);
        out.key("tangency_margin");
        write_number(out, m.tangency_margin);
        out.key("distance_ratio");
        write_number(out, m.distance_ratio);
        out.end_object();
    }
    out.end_object();
}

case_points::case_points(std::vector<audit_target> targets, std::vector<std::string> labels)
    : targets_(std::move(targets)), labels_(std::move(labels)) {}

namespace {

bool by_sample_key(const std::pair<case_points::sample_key, case_points::row>& a,
                   const std::pair<case_points::sample_key, case_points::row>& b) {
    return a.first < b.first;
}

}  // namespace

void case_points::insert(const std::string& family, const sample_key& key, row r) {
    kept_rows& kept = sample_[family];
    if (kept.size() >= per_family) {
        if (!(key < kept.front().first)) return;
        // The largest key leaves; the new row takes its place.
        std::pop_heap(kept.begin(), kept.end(), by_sample_key);
        kept.back() = {key, std::move(r)};
    } else {
        kept.emplace_back(key, std::move(r));
    }
    std::push_heap(kept.begin(), kept.end(), by_sample_key);
}

bool case_points::would_keep(const std::string& family, const sample_key& key) const {
    const auto found = sample_.find(family);
    return found == sample_.end() || found->second.size() < per_family || key < found->second.front().first;
}

void case_points::for_each_in_key_order(
    const std::function<void(const std::string& family, const sample_key& key, const row& r)>& visit) const {
    for (const auto& [family, kept] : sample_) {
        std::vector<const std::pair<sample_key, row>*> ordered;
        ordered.reserve(kept.size());
        for (const auto& entry : kept) ordered.push_back(&entry);
        std::sort(ordered.begin(), ordered.end(), [](const auto* a, const auto* b) { return by_sample_key(*a, *b); });
        for (const auto* entry : ordered) visit(family, entry->first, entry->second);
    }
}

void case_points::add(const audited_case& c, std::size_t index) {
    const case_stability& s = c.stability;
    const sample_key key{id_hash(c.source->id), index};
    if (!would_keep(c.source->family, key)) return;
    const auto kappa = [](const std::optional<stability_measures>& m) -> std::optional<double> {
        if (!m || !m->valid) return std::nullopt;
        return m->near_condition;
    };
    row r;
    r.index = index;
    r.family = c.source->family;
    r.kappa_float = kappa(s.at_float);
    r.kappa_double = kappa(s.at_double);
    if (s.at_double && s.at_double->valid) r.ratio = s.at_double->distance_ratio;
    // Sized once, empty, and each present value assigned in place: an
    // optional pushed back was assembled on the stack from two stores and
    // read back as one, a stall that was most of this function's time.
    r.per_target.resize(targets_.size());
    for (std::size_t t = 0; t < targets_.size(); ++t) {
        const case_score& score = c.outcomes[t].score;
        row::target_point& point = r.per_target[t];
        point.verdict = score.verdict;
        if (score.cause) point.cause = *score.cause;
        if (score.verdict != verdict_kind::agree || !score.near_ulp) continue;
        // A figure kept to its bucket is printed as its exact value (printed_as_exact).
        if (score.figure_upper_bounds && !printed_alike(*score.near_ulp, score.figure_upper_bounds->near_ulp))
            point.near_ulp = c.every_digit(t, targets_[t]).near_ulp;
        else
            point.near_ulp = *score.near_ulp;
    }
    insert(c.source->family, key, std::move(r));
}

void case_points::merge(const case_points& other) {
    for (const auto& [family, kept] : other.sample_)
        for (const auto& [key, r] : kept)
            if (would_keep(family, key)) insert(family, key, r);  // a row is copied only when it is kept
}

json case_points::to_json() const {
    std::vector<const row*> rows;
    for (const auto& [family, kept] : sample_)
        for (const auto& [key, r] : kept) rows.push_back(&r);
    std::sort(rows.begin(), rows.end(), [](const row* a, const row* b) { return a->index < b->index; });
    json family = json::array(), ratio = json::array(), kappa_float = json::array(), kappa_double = json::array();
    std::vector<json> verdict(targets_.size(), json::array()), near_ulp(targets_.size(), json::array()),
        cause(targets_.size(), json::array());
    for (const row* r : rows) {
        family.push_back(r->family);
        ratio.push_back(optional_number(r->ratio));
        kappa_float.push_back(optional_number(r->kappa_float));
        kappa_double.push_back(optional_number(r->kappa_double));
        for (std::size_t t = 0; t < targets_.size(); ++t) {
            const row::target_point& point = r->per_target[t];
            verdict[t].push_back(verdict_name(point.verdict));
            near_ulp[t].push_back(optional_number(printed_figure(point.near_ulp)));
            cause[t].push_back(point.cause ? json(cause_name(*point.cause)) : json());
        }
    }
    // The columns are moved into place: a brace-initialised json copies
    // every value it is given, and these hold a value per kept case and target.
    json targets = json::object();
    reserve_members(targets, targets_.size());
    for (std::size_t t = 0; t < targets_.size(); ++t) {
        json& entry = targets[labels_[t]];
        entry = json::object();
        reserve_members(entry, 5);
        entry["variant"] = targets_[t].subject.name;
        entry["precision_of_inputs"] = precision_name(targets_[t].prec);
        entry["verdict"] = std::move(verdict[t]);
        entry["near_ulp"] = std::move(near_ulp[t]);
        entry["cause"] = std::move(cause[t]);
    }
    json out = json::object();
    reserve_members(out, 6);
    out["cases"] = rows.size();
    out["sample"] = fmt::format(
        "per family, the {} cases with the smallest hash of their id (every case of a smaller family), in input order",
        per_family);
    out["family"] = std::move(family);
    out["distance_ratio"] = std::move(ratio);
    json& condition = out["condition"];
    condition = json::object();
    reserve_members(condition, 2);
    condition["float"] = std::move(kappa_float);
    condition["double"] = std::move(kappa_double);
    out["targets"] = std::move(targets);
    return out;
}

namespace {

// The repetitions' distribution-free confidence interval for the median (bench/timing.h).
json median_interval_json(const std::vector<double>& repetitions) {
    const bench::median_interval i = bench::median_confidence_interval(repetitions);
    return {{"low", i.low}, {"high", i.high}, {"confidence", i.confidence}};
}

}  // namespace

json timing_json(const std::vector<bench::timing_row>& rows, const bench::timing_options& options,
                 const std::string& reference_label) {
    std::map<std::string, double> reference;  // family → reference median
    for (const auto& r : rows)
        if (r.label() == reference_label) reference[r.family] = r.median;
    json out;
    out["harness"] = {{"library", "Google Benchmark " RAYVERIFY_BENCHMARK_VERSION},
                      {"repetitions", options.repetitions},
                      {"min_time_per_repetition_s", options.min_time_s},
                      {"warmup_s", options.warmup_s},
                      {"clock", "CPU time of the process (wall-clock time recorded beside it)"},
                      {"loop", "one pass over the family's cases valid at that precision, pre-rounded; the "
                               "intersector template instantiated on its concrete function (no std::function), "
                               "each result passed to benchmark::DoNotOptimize"},
                      {"long_double", "x87 80-bit arithmetic on the double inputs, roots rounded to double"},
                      {"exact_oracle", "solve_exact on the double inputs: the filtered oracle (class, signs, "
                                       "correctly rounded roots and hit point; exact arithmetic only where the "
                                       "double-double filter cannot decide)"},
                      {"exact_reference", "solve_exact_reference on the double inputs: the same answers from exact "
                                          "arithmetic alone, no filter"},
                      {"plugins", "a --plugin run in process is timed in its own loop: one pass over the same "
                                  "cases through its entry point (a function pointer per test; a version 2 "
                                  "plugin's batch function once per pass), its arguments laid out before the "
                                  "timing, its guard buffer, crash marker and floating-point environment set and "
                                  "checked once per pass; an isolated plugin, or an engine port (a variant with a "
                                  "build), is called through its function per test (the other built-in variants "
                                  "are inlined)"}};
    out["reference"] = reference_label;
    json table = json::array();
    std::map<std::string, std::pair<double, std::size_t>> totals;  // label → (Σ ns·cases, Σ cases)
    std::vector<std::string> order;
    for (const auto& r : rows) {
        json ratio = nullptr;
        if (reference.count(r.family) && reference[r.family] > 0) ratio = r.median / reference[r.family];
        table.push_back({{"variant", r.variant},
                         {"precision", r.precision},
                         {"family", r.family},
                         {"cases", r.cases},
                         {"ns_per_test", {{"median", r.median}, {"min", r.min}, {"max", r.max},
                                          {"median_interval", median_interval_json(r.ns_per_test)},
                                          {"repetitions", r.ns_per_test}}},
                         {"real_ns_per_test_median", r.real_median},
                         {"ratio_to_reference", ratio},
                         {"checksum_hits", r.checksum}});
        if (!totals.count(r.label())) order.push_back(r.label());
        auto& [weighted, cases] = totals[r.label()];
        weighted += r.median * static_cast<double>(r.cases);
        cases += r.cases;
    }
    out["rows"] = table;
    json summary = json::array();
    const double reference_total =
        totals.count(reference_label) && totals[reference_label].second
            ? totals[reference_label].first / static_cast<double>(totals[reference_label].second)
            : 0;
    for (const std::string& label : order) {
        const auto& [weighted, cases] = totals[label];
        const double ns = cases ? weighted / static_cast<double>(cases) : 0;
        const auto slash = label.find('/');
        summary.push_back({{"variant", label.substr(0, slash)},
                           {"precision", label.substr(slash + 1)},
                           {"cases", cases},
                           {"ns_per_test", ns},
                           {"ratio_to_reference", reference_total > 0 ? json(ns / reference_total) : json(nullptr)}});
    }
    out["overall"] = summary;
    out["overall_definition"] = "case-weighted mean of the per-family medians: ns for one pass over every case";
    return out;
}

}  // namespace rayverify
