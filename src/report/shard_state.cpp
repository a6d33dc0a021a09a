#include "report/shard_state.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <limits>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "corpus/case_stream.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "report/audit_report.h"
#include "report/case_list.h"
#include "report/contract_hints.h"

namespace rayverify {

using json = nlohmann::ordered_json;

audit_state::audit_state(const std::vector<audit_target>& targets)
    : audit(targets), stability(targets), points(targets, target_labels(targets)), lint(targets),
      examples(targets.size()) {}

void audit_state::merge(const audit_state& other) {
    audit.merge(other.audit);
    stability.merge(other.stability);
    points.merge(other.points);
    lint.merge(other.lint);
    examples.merge(other.examples);
}

std::vector<std::string> target_labels(const std::vector<audit_target>& targets) {
    std::vector<std::string> labels;
    for (const audit_target& t : targets) labels.push_back(t.label());
    return labels;
}

json audit_report_document(const audit_state& state, const audit_totals& totals, const run_context& context,
                           unsigned threads) {
    json report = audit_report_json(totals, context);
    report["stability"] = stability_json(totals, state.stability.finish(threads));
    report["case_points"] = state.points.to_json();
    report["contract_hints"] = contract_hints_json(totals.targets, state.lint.hints());
    report["cases_to_open"] = cases_to_open_json(totals.targets, state.examples);
    return report;
}

namespace {

// A histogram's buckets as one string, "key:count,Δkey:count,...", each key
// after the first as its distance from the one before: one JSON value per
// histogram, not two arrays and two numbers per bucket (parsing the states is
// most of a merge's time).
std::string buckets_text(const error_summary::histogram_map& buckets) {
    std::string text;
    std::uint64_t previous = 0;
    for (const auto& [bucket, n] : buckets) {
        text += fmt::format("{}{}:{}", text.empty() ? "" : ",", bucket - previous, n);
        previous = bucket;
    }
    return text;
}

// The (bucket, count) pairs of such a list, in key order; nullopt when `text` is not one.
std::optional<std::vector<std::pair<std::uint64_t, std::size_t>>> buckets_from_text(std::string_view text) {
    std::vector<std::pair<std::uint64_t, std::size_t>> buckets;
    std::uint64_t key = 0;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t comma = std::min(text.find(',', at), text.size());
        const std::string_view pair = text.substr(at, comma - at);
        const std::size_t colon = pair.find(':');
        std::uint64_t step = 0;
        std::size_t n = 0;
        if (colon == std::string_view::npos || !parse_unsigned(pair.substr(0, colon), step) ||
            !parse_unsigned(pair.substr(colon + 1), n) || (at > 0 && step == 0) || key + step < key)
            return std::nullopt;
        key += step;
        buckets.emplace_back(key, n);
        at = comma + 1;
    }
    return buckets;
}

// The header a document is read against: the shard's cases, targets and families.
struct state_context {
    const shard_header& header;
    const std::map<std::string, std::size_t>* cases_by_family = nullptr;  // once state.audit has read it
};

const state_context& context_of(const json_io& io) { return *io.context<state_context>(); }

// A global case index of the shard's cases, as member `key` of io's value.
void check_case_index(const json_io& io, std::string_view key, std::size_t i) {
    const shard_header& h = context_of(io).header;
    if (i >= h.input.cases) io.fail(key, fmt::format("is {}, beyond the input's {} cases", i, h.input.cases));
    if (!h.shard.owns(i))
        io.fail(key, fmt::format("is {}, a case of shard {}/{}, not of this shard {}", i, i % h.shard.count + 1,
                                 h.shard.count, h.shard.text()));
}

// A family of the shard's cases (state.audit.cases_by_family).
void check_family(const json_io& io, std::string_view key, const std::string& family) {
    const auto* families = context_of(io).cases_by_family;
    if (families != nullptr && !families->count(family))
        io.fail(key, fmt::format("{} is not a family of the shard", json_io::quoted(family)));
}

void check_fingerprint_text(const json_io& io, std::string_view key, const std::string& text) {
    if (!is_fingerprint_text(text)) io.fail(key, fmt::format("{} is not 16 hex digits", json_io::quoted(text)));
}

// The first value where two documents differ: its path below `at` and the
// value in each (null where a document lacks it).
struct json_difference {
    std::string path;
    const json *in_a, *in_b;
};

std::optional<json_difference> first_difference(const json& a, const json& b, const std::string& at) {
    if (a.type() != b.type() || (!a.is_structured() && a != b)) return json_difference{at, &a, &b};
    if (a.is_array()) {
        if (a.size() != b.size()) return json_difference{at, &a, &b};
        for (std::size_t i = 0; i < a.size(); ++i)
            if (auto d = first_difference(a[i], b[i], fmt::format("{}[{}]", at, i))) return d;
    } else if (a.is_object()) {
        for (const auto& [key, value] : a.items()) {
            const auto in_b = b.find(key);
            if (in_b == b.end()) return json_difference{at + "." + key, &value, nullptr};
            if (auto d = first_difference(value, *in_b, at + "." + key)) return d;
        }
        if (a.size() != b.size()) return json_difference{at, &a, &b};
    }
    return std::nullopt;
}

}  // namespace

// An error summary: its count, maximum (a hex float ≥ 0, never NaN), the case
// holding it and the histogram (buckets_text), all consistent.
static void map_json(json_io& io, error_summary& s) {
    io.field("count", s.count);
    io.field("max", s.max);
    io.field("max_index", s.max_index);
    io.field("max_id", s.max_id);
    std::string buckets = io.reading() ? "" : buckets_text(s.histogram());
    io.field("buckets", buckets);
    if (!io.reading()) return;
    if (std::isnan(s.max) || s.max < 0)
        io.fail("max", fmt::format("is {}, expected an error ≥ 0 (never NaN)", hex_float(s.max)));
    const std::size_t count = s.count;
    const auto stored = buckets_from_text(buckets);
    if (!stored) io.fail("buckets", "is not a list of key:count pairs, each key after the first above the one before");
    // Each bucket checked before the summary holds it: a key beyond the last
    // bucket has no place in the summary's blocks.
    std::size_t in_buckets = 0;
    std::uint64_t last = 0;
    const std::uint64_t last_bucket = error_summary::bucket_of(std::numeric_limits<double>::infinity());
    for (const auto& [key, size] : *stored) {
        const std::string at = fmt::format("buckets (key {})", key);
        if (key > last_bucket) io.fail(at, fmt::format("is beyond the last bucket ({}, infinity)", last_bucket));
        if (size == 0) io.fail(at, "holds 0 errors: an empty bucket is not stored");
        if (in_buckets + size < in_buckets) io.fail(at, "overflows the count");
        in_buckets += size;
        last = key;
        s.add_to_bucket(key, size);
    }
    if (in_buckets != count) io.fail("count", fmt::format("is {}, but its buckets hold {} errors", count, in_buckets));
    if (count == 0 && (s.max != 0 || s.max_index != 0 || !s.max_id.empty()))
        io.fail("max", "is set although the summary holds no error");
    if (count > 0) {
        check_case_index(io, "max_index", s.max_index);
        if (error_summary::bucket_of(s.max) != last)
            io.fail("max", fmt::format("is {}, not in the summary's last bucket (the maximum must be the largest error)",
                                       hex_float(s.max)));
    }
}

// One target's tallies over some cases: verdicts and causes that add up, error figures over the agreeing cases.
static void map_json(json_io& io, target_samples& s) {
    io.field("cases", s.cases);
    io.field("verdicts", s.verdicts, [](std::size_t k) { return verdict_name(static_cast<verdict_kind>(k)); });
    io.field("causes", s.causes, [](std::size_t c) { return cause_name(static_cast<disagreement_cause>(c)); });
    for (const error_figure_definition& f : error_figures) io.field(std::string(f.name).c_str(), s.errors[f.figure]);
    if (!io.reading()) return;
    std::size_t total = 0, disagreeing = 0, caused = 0;
    for (int k = 0; k < verdict_kind_count; ++k) {
        total += s.verdicts[k];
        if (is_disagreement(static_cast<verdict_kind>(k))) disagreeing += s.verdicts[k];
    }
    for (std::size_t n : s.causes) caused += n;
    if (total != s.cases) io.fail("verdicts", fmt::format("add up to {}, but the target has {} cases", total, s.cases));
    if (caused != disagreeing)
        io.fail("causes", fmt::format("add up to {}, but the target has {} disagreements", caused, disagreeing));
    const std::size_t agreeing = s.verdicts[static_cast<int>(verdict_kind::agree)];
    for (const error_figure_definition& f : error_figures)
        if (s.errors[f.figure].count > agreeing)
            io.fail(std::string(f.name) + ".count",
                    fmt::format("is {}, more than the {} agreeing cases", s.errors[f.figure].count, agreeing));
}

static void map_json(json_io& io, invalid_case& c) {
    io.field("index", c.index);
    io.field("id", c.id);
    io.field("source", c.source);
    io.field("float", c.at_float);
    io.field("double", c.at_double);
    if (io.reading()) check_case_index(io, "index", c.index);
}

static void map_json(json_io& io, bucket_tally& t) {
    io.field("cases", t.cases);
    io.field("misclassified", t.misclassified);
    io.field("disagreements", t.disagreements);
    io.field("conditioning_limited", t.conditioning_limited);
    io.field("algorithmic", t.algorithmic);
    io.field("by_design", t.by_design);
    if (io.reading() && (t.misclassified > t.disagreements || t.disagreements > t.cases ||
                         t.conditioning_limited + t.algorithmic + t.by_design != t.disagreements))
        io.fail("is inconsistent: expected misclassified ≤ disagreements ≤ cases and the three causes "
                "(conditioning-limited, algorithmic, by design) adding up to the disagreements");
}

static void map_json(json_io& io, stability_samples& s) {
    io.field("buckets", s.buckets);
    io.field("near_ulp", s.near_ulp);
    io.field("excess", s.excess);
    io.field("above_line", s.above_line);
    io.field("well_conditioned", s.well_conditioned);
    io.field("well_conditioned_above", s.well_conditioned_above);
    if (!io.reading()) return;
    std::size_t scored = 0;
    for (int b = 0; b < condition_bucket_count; ++b) {
        if (s.near_ulp[b].count > s.buckets[b].cases - s.buckets[b].disagreements)
            io.fail(fmt::format("near_ulp[{}].count", b), "is more than the bucket's agreeing cases");
        scored += s.buckets[b].cases;
    }
    const std::size_t shard_cases = context_of(io).header.cases;
    if (scored > shard_cases) io.fail("buckets", fmt::format("hold {} cases, the shard has {}", scored, shard_cases));
    if (s.above_line > s.excess.count || s.well_conditioned > s.excess.count ||
        s.well_conditioned_above > std::min(s.above_line, s.well_conditioned))
        io.fail("above_line", "and well_conditioned(_above) are inconsistent with each other and with excess.count");
}

static void map_json(json_io& io, contract_lint_tally& t) {
    io.field("scored", t.scored);
    io.field("wrong", t.wrong);
    io.field("fixed", t.fixed);
    io.field("broken", t.broken);
    if (!io.reading()) return;
    if (t.wrong > t.scored) io.fail("wrong", "is more than the cases scored");
    if (t.broken.size() != t.fixed.size())
        io.fail("broken", fmt::format("has {} entries, fixed {}", t.broken.size(), t.fixed.size()));
    for (std::size_t k = 0; k < t.fixed.size(); ++k) {
        if (t.fixed[k] > t.wrong) io.fail(fmt::format("fixed[{}]", k), "is more than the disagreements");
        if (t.broken[k] > t.scored - t.wrong) io.fail(fmt::format("broken[{}]", k), "is more than the agreeing cases");
    }
}

namespace {

// A per-target list of the whole run ("overall", which a reader forms again
// from the families) and per family: both read and checked, the families'
// lists one entry per target, and the whole run's equal to their merge value
// for value (an edited overall figure would otherwise pass unnoticed).
template <class Samples>
void map_per_target(json_io& io, const std::vector<audit_target>& targets,
                    std::map<std::string, std::vector<Samples>>& by_family) {
    std::vector<Samples> overall;
    if (!io.reading()) overall = merged_over_families(by_family, targets.size());
    io.field("overall", overall);
    io.field("by_family", by_family);
    if (!io.reading()) return;
    const auto one_per_target = [&](const std::vector<Samples>& list, const std::string& key) {
        if (list.size() != targets.size())
            io.fail(key, fmt::format("has {} entries, expected {}", list.size(), targets.size()));
    };
    one_per_target(overall, "overall");
    const auto& families = *context_of(io).cases_by_family;
    for (const auto& [family, list] : by_family) {
        const std::string key = "by_family." + printable(family);
        if (!families.count(family)) io.fail(key, "is a family not in state.audit.cases_by_family");
        one_per_target(list, key);
    }
    if (by_family.size() != families.size()) io.fail("by_family", "lacks a family of state.audit.cases_by_family");
    const json stored = to_json_mapped(overall), merged = to_json_mapped(merged_over_families(by_family, targets.size()));
    if (const auto d = first_difference(stored, merged, "overall")) {
        const auto shown = [](const json* value) -> std::string { return value != nullptr ? json_io::shown(*value) : "absent"; };
        io.fail(d->path, fmt::format("is {}, but the families' figures merge to {}", shown(d->in_a), shown(d->in_b)));
    }
}

void map_audit(json_io& io, audit_accumulator& a, const std::vector<audit_target>& targets) {
    io.field("cases", a.cases);
    io.field("cases_by_family", a.cases_by_family);
    io.field("invalid", a.invalid);
    io.field("invalid_list", a.invalid_list);
    if (io.reading()) {
        const shard_header& header = context_of(io).header;
        if (a.cases != header.cases)
            io.fail("cases", fmt::format("is {}, but shard.cases is {}", a.cases, header.cases));
        std::size_t family_total = 0;
        for (const auto& [family, n] : a.cases_by_family) family_total += n;
        if (family_total != a.cases)
            io.fail("cases_by_family", fmt::format("add up to {}, but the shard has {} cases", family_total, a.cases));
        std::array<std::size_t, 2> listed{};
        for (std::size_t i = 0; i < a.invalid_list.size(); ++i) {
            const invalid_case& c = a.invalid_list[i];
            if (i > 0 && c.index <= a.invalid_list[i - 1].index)
                io.fail(fmt::format("invalid_list[{}].index", i), "is not above the index before it");
            listed[0] += c.at_float != invalid_reason::none;
            listed[1] += c.at_double != invalid_reason::none;
        }
        for (int p = 0; p < 2; ++p)
            if (a.invalid[p] != listed[p])
                io.fail(fmt::format("invalid[{}]", p), fmt::format("is {}, but invalid_list holds {} cases invalid in {}",
                                                                  a.invalid[p], listed[p], p == 0 ? "float" : "double"));
    }
    map_per_target(io, targets, a.by_family);
    if (!io.reading()) return;
    // Each family's tallies cover its cases.
    for (const auto& [family, list] : a.by_family)
        for (std::size_t t = 0; t < list.size(); ++t)
            if (list[t].cases != a.cases_by_family.at(family))
                io.fail(fmt::format("by_family.{}[{}].cases", printable(family), t),
                        fmt::format("is {}, expected {}", list[t].cases, a.cases_by_family.at(family)));
}

// A case the plots draw, as the state keeps it: its family's key and the
// sample key beside the row.
struct case_point_record {
    std::string family_key;
    case_points::sample_key key;
    case_points::row row;
};

void map_json(json_io& io, case_point_record& p) {
    io.field("family_key", p.family_key);
    io.field("hash", p.key.first);
    io.field("index", p.row.index);
    io.field("family", p.row.family);
    io.field("ratio", p.row.ratio);
    io.field("kappa_float", p.row.kappa_float);
    io.field("kappa_double", p.row.kappa_double);
    // The row's targets as three columns, as the plots' sample prints them.
    std::vector<verdict_kind> verdict;
    std::vector<std::optional<double>> near_ulp;
    std::vector<std::optional<disagreement_cause>> cause;
    if (!io.reading())
        for (const case_points::row::target_point& point : p.row.per_target) {
            verdict.push_back(point.verdict);
            near_ulp.push_back(point.near_ulp);
            cause.push_back(point.cause);
        }
    io.field("verdict", verdict);
    io.field("near_ulp", near_ulp);
    io.field("cause", cause);
    if (!io.reading()) return;
    p.key.second = p.row.index;
    check_family(io, "family_key", p.family_key.empty() ? "-" : p.family_key);  // the audit counts it as "-"
    check_case_index(io, "index", p.row.index);
    const std::size_t targets = context_of(io).header.targets.size();
    if (verdict.size() != targets)
        io.fail("verdict", fmt::format("has {} entries, expected {}", verdict.size(), targets));
    if (near_ulp.size() != targets)
        io.fail("near_ulp", fmt::format("has {} entries, expected {}", near_ulp.size(), targets));
    if (cause.size() != targets)
        io.fail("cause", fmt::format("has {} entries, expected {}", cause.size(), targets));
    p.row.per_target.resize(targets);
    for (std::size_t t = 0; t < targets; ++t) p.row.per_target[t] = {verdict[t], near_ulp[t], cause[t]};
}

// A case kept to open (compare/case_examples.h), as the state keeps it: the
// list it is in ("first", "worst" of a verdict, "farthest") and the case as a corpus line.
struct case_example_record {
    std::size_t target = 0;
    std::string kind;
    verdict_kind verdict = verdict_kind::agree;
    case_example example;
};

void map_json(json_io& io, case_example_record& r) {
    const std::size_t targets = context_of(io).header.targets.size();
    io.field("target", r.target);
    if (io.reading() && r.target >= targets) io.fail("target", fmt::format("is beyond the {} targets", targets));
    io.field("kind", r.kind);
    if (io.reading() && r.kind != "first" && r.kind != "worst" && r.kind != "farthest")
        io.fail("kind", fmt::format("{} is not first, worst or farthest", json_io::quoted(r.kind)));
    io.field("verdict", r.verdict);
    io.field("index", r.example.index);
    io.field("error", r.example.error);
    std::string line = io.reading() ? "" : format_case_line(r.example.kase);
    io.field("line", line);
    io.field("source", r.example.kase.source);
    io.nullable_field("cause", r.example.cause);
    if (!io.reading()) return;
    check_case_index(io, "index", r.example.index);
    if (std::isnan(r.example.error) || r.example.error < 0)
        io.fail("error", fmt::format("is {}, expected an error ≥ 0 (never NaN)", hex_float(r.example.error)));
    std::vector<corpus_case> parsed;
    try {
        parsed = parse_corpus(r.example.kase.source, line, false);
    } catch (const input_error& problem) {
        io.fail("line", problem.what());
    }
    if (parsed.size() != 1) io.fail("line", "is not one corpus line");
    const std::string source = std::move(r.example.kase.source);
    r.example.kase = std::move(parsed[0]);
    r.example.kase.source = source;
}

}  // namespace

static void map_json(json_io& io, audit_accumulator& a) { map_audit(io, a, a.targets); }

static void map_json(json_io& io, stability_accumulator& s) { map_per_target(io, s.targets, s.by_family); }

static void map_json(json_io& io, audit_state& state) {
    const std::vector<audit_target>& targets = state.audit.targets;
    io.field("audit", state.audit);  // through map_json(audit_accumulator) below
    io.field("stability", state.stability);

    std::vector<case_point_record> points;
    if (!io.reading())
        state.points.for_each_in_key_order([&points](const std::string& family, const case_points::sample_key& key,
                                                     const case_points::row& row) { points.push_back({family, key, row}); });
    io.field("case_points", points);

    std::vector<case_example_record> examples;
    if (!io.reading())
        for (std::size_t t = 0; t < state.examples.first.size(); ++t) {
            for (int k = 0; k < verdict_kind_count; ++k)
                for (const case_example& e : state.examples.first[t][k])
                    examples.push_back({t, "first", static_cast<verdict_kind>(k), e});
            for (int k = 0; k < verdict_kind_count; ++k)
                for (const case_example& e : state.examples.worst[t][k])
                    examples.push_back({t, "worst", static_cast<verdict_kind>(k), e});
            for (const case_example& e : state.examples.farthest[t]) examples.push_back({t, "farthest", verdict_kind::agree, e});
        }
    io.field("cases_to_open", examples);
    io.field("contract_lint", state.lint.tallies);
    if (!io.reading()) return;

    std::map<std::string, std::size_t> per_family;
    for (std::size_t i = 0; i < points.size(); ++i) {
        case_point_record& p = points[i];
        if (++per_family[p.family_key] > case_points::per_family)
            io.fail(fmt::format("case_points[{}]", i),
                    fmt::format("is one more than the {} points a family keeps", case_points::per_family));
        state.points.insert(p.family_key, p.key, std::move(p.row));
    }
    for (case_example_record& r : examples) {
        if (r.kind == "farthest")
            state.examples.farthest[r.target].push_back(std::move(r.example));
        else
            (r.kind == "first" ? state.examples.first : state.examples.worst)[r.target][static_cast<int>(r.verdict)]
                .push_back(std::move(r.example));
    }
    if (state.lint.tallies.size() != targets.size())
        io.fail("contract_lint", fmt::format("has {} entries, expected {}", state.lint.tallies.size(), targets.size()));
}

void map_json(json_io& io, shard_header::digests_record& d) {
    io.nullable_field("results", d.results);
    io.field("plugins", d.plugins);
    if (!io.reading()) return;
    if (d.results) check_fingerprint_text(io, "results", *d.results);
    for (std::size_t i = 0; i < d.plugins.size(); ++i) check_fingerprint_text(io, fmt::format("plugins[{}]", i), d.plugins[i]);
}

static void map_json(json_io& io, shard_header::input_record& in) {
    io.field("paths", in.paths);
    io.field("generated", in.generated);
    io.field("cases", in.cases);
    io.field("fingerprint", in.fingerprint);
    if (io.reading()) check_fingerprint_text(io, "fingerprint", in.fingerprint);
    io.field("digests", in.digests);
}

void map_json(json_io& io, shard_header& h) {
    io.field("schema_version", h.schema_version);
    io.field("format", h.format);
    if (io.reading() && h.format != shard_state_format)
        io.fail("format", fmt::format("{}, this rayverify reads '{}'", json_io::quoted(h.format), shard_state_format));
    io.field("build", h.build);
    if (io.reading() && !h.build.is_object()) io.fail("build", "is not a JSON object");
    io.field("command", h.command);
    io.field("input", h.input);
    std::size_t index = h.shard.index, count = h.shard.count;
    const auto shard_fields = [&](json_io& s) {
        s.field("index", index);
        s.field("count", count);
        s.field("cases", h.cases);
    };
    io.object("shard", shard_fields);
    if (io.reading()) {
        if (count == 0) io.fail("shard.count", "is 0, expected a number of shards ≥ 1");
        if (index == 0 || index > count)
            io.fail("shard.index", fmt::format("is {}, expected 1 to shard.count ({})", index, count));
        h.shard = {index, count};
    }
    io.field("targets", h.targets);
    if (io.reading() && h.targets.empty()) io.fail("targets", "is empty");
    io.nullable_field("per_case_file", h.per_case_file);
    io.nullable_field("per_case_digest", h.per_case_digest);
    if (!io.reading() || !h.per_case_file) return;
    const std::filesystem::path path(*h.per_case_file);
    const bool inside = !path.empty() && path.is_relative() && !path.has_root_name() &&
                        std::none_of(path.begin(), path.end(), [](const auto& part) { return part == ".."; });
    if (!inside)
        io.fail("per_case_file",
                fmt::format("{} is not a path inside the shard directory", json_io::quoted(path.string())));
    if (!h.per_case_digest) io.fail("per_case_digest", "is null, but the shard wrote a per-case file");
    check_fingerprint_text(io, "per_case_digest", *h.per_case_digest);
}

namespace {

// Builds a document up to the top-level key "state" and stops there: the
// audit writes "state" last, after everything the consistency checks read,
// so a header costs a few kilobytes of parsing whatever the state's size.
class header_reader : public nlohmann::json_sax<json> {
public:
    explicit header_reader(json& document) : dom_(document) {}
    bool null() override { return dom_.null(); }
    bool boolean(bool value) override { return dom_.boolean(value); }
    bool number_integer(number_integer_t value) override { return dom_.number_integer(value); }
    bool number_unsigned(number_unsigned_t value) override { return dom_.number_unsigned(value); }
    bool number_float(number_float_t value, const string_t& text) override { return dom_.number_float(value, text); }
    bool string(string_t& value) override { return dom_.string(value); }
    bool binary(binary_t& value) override { return dom_.binary(value); }
    bool start_object(std::size_t n) override { return ++depth_, dom_.start_object(n); }
    bool key(string_t& value) override { return !(depth_ == 1 && value == "state") && dom_.key(value); }
    bool end_object() override { return --depth_, dom_.end_object(); }
    bool start_array(std::size_t n) override { return ++depth_, dom_.start_array(n); }
    bool end_array() override { return --depth_, dom_.end_array(); }
    bool parse_error(std::size_t position, const std::string& token, const nlohmann::detail::exception& e) override {
        return dom_.parse_error(position, token, e);
    }

private:
    nlohmann::detail::json_sax_dom_parser<json> dom_;  // what json::parse builds with (nlohmann 3.11)
    int depth_ = 0;
};

}  // namespace

json read_shard_document(const std::filesystem::path& file, bool header_only) {
    std::error_code error;
    if (std::filesystem::exists(file, error) && !std::filesystem::is_regular_file(file, error))  // a FIFO would block the merge
        throw input_error(file.string(), 0, "",
                          "is not a regular file (a FIFO, a device or a socket): a shard's state is a file");
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw input_error(file.string(), 0, "",
                          "cannot open: not the report directory of a `rayverify audit --shard K/N --report DIR` run");
    try {
        json state;
        if (header_only) {
            header_reader reader(state);
            json::sax_parse(in, &reader);
        } else {
            std::ostringstream text;
            text << in.rdbuf();
            state = json::parse(std::move(text).str());
        }
        return state;
    } catch (const json::parse_error& e) {
        throw input_error(file.string(), 0, "", fmt::format("not a shard state: {}", e.what()));
    }
}


json shard_document(const shard_header& header, const audit_state& state) {
    json doc = to_json_mapped(header);
    const state_context context{header, &state.audit.cases_by_family};
    json_io io(doc, &context);
    io.field("state", const_cast<audit_state&>(state));  // a mapping only reads its value when writing
    return doc;
}

shard_header read_shard_header(const json& doc, const std::string& file) {
    return from_json_mapped<shard_header>(doc, file);
}

audit_state read_shard_state(const json& doc, const std::string& file, const shard_header& header) {
    audit_state state(header.targets);
    const state_context context{header, &state.audit.cases_by_family};  // filled as state.audit is read
    json_io io(doc, file, &context);
    io.field("state", state);
    return state;
}

}  // namespace rayverify
