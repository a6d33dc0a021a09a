#include "report/shard_state.h"

#include <fmt/format.h>

#include <deque>
#include <mutex>

#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "report/audit_report.h"

namespace rayverify {

using json = nlohmann::ordered_json;

audit_state::audit_state(const std::vector<audit_target>& targets)
    : audit(targets), stability(targets), points(targets, target_labels(targets)) {}

void audit_state::merge(const audit_state& other) {
    audit.merge(other.audit);
    stability.merge(other.stability);
    points.merge(other.points);
}

std::vector<std::string> target_labels(const std::vector<audit_target>& targets) {
    std::vector<std::string> labels;
    for (const audit_target& t : targets) labels.push_back(t.label());
    return labels;
}

json audit_report_document(const audit_state& state, const run_context& context) {
    const audit_totals totals = state.audit.finish();
    json report = audit_report_json(totals, context);
    report["stability"] = stability_json(totals, state.stability.finish());
    report["case_points"] = state.points.to_json();
    return report;
}

namespace {

json double_json(double x) { return hex_float(x); }
double double_from(const json& j) { return parse_exact_double(j.get<std::string>(), "shard state", 0, "value"); }

// A histogram's buckets as one string, "key:count,Δkey:count,...", each key
// after the first as its distance from the one before: one JSON value instead
// of two arrays and two numbers per bucket, which made parsing the states
// nearly all of a merge's time.
std::string buckets_text(const decltype(error_summary::buckets)& buckets) {
    std::string text;
    std::uint64_t previous = 0;
    for (const auto& [bucket, n] : buckets) {
        text += fmt::format("{}{}:{}", text.empty() ? "" : ",", bucket - previous, n);
        previous = bucket;
    }
    return text;
}

void buckets_from_text(const json& j, decltype(error_summary::buckets)& buckets) {
    const std::string& text = j.get_ref<const std::string&>();
    std::uint64_t key = 0;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t comma = std::min(text.find(',', at), text.size());
        const std::string_view pair = std::string_view(text).substr(at, comma - at);
        const std::size_t colon = pair.find(':');
        std::uint64_t step = 0;
        std::size_t n = 0;
        if (colon == std::string_view::npos || !parse_unsigned(pair.substr(0, colon), step) ||
            !parse_unsigned(pair.substr(colon + 1), n) || (at > 0 && step == 0))
            throw json::other_error::create(501, fmt::format("malformed buckets at '{}'", pair), &j);
        key += step;
        buckets.emplace_hint(buckets.end(), key, n);
        at = comma + 1;
    }
}

json summary_json(const error_summary& s) {
    return {{"count", s.count}, {"max", double_json(s.max)}, {"max_index", s.max_index}, {"max_id", s.max_id},
            {"buckets", buckets_text(s.buckets)}};
}

error_summary summary_from(const json& j) {
    error_summary s;
    s.count = j.at("count").get<std::size_t>();
    s.max = double_from(j.at("max"));
    s.max_index = j.at("max_index").get<std::size_t>();
    s.max_id = j.at("max_id").get<std::string>();
    buckets_from_text(j.at("buckets"), s.buckets);
    return s;
}

json samples_json(const target_samples& s) {
    return {{"cases", s.cases},           {"verdicts", s.verdicts},          {"causes", s.causes},
            {"near_ulp", summary_json(s.near_ulp)}, {"far_ulp", summary_json(s.far_ulp)},
            {"hit_ulp", summary_json(s.hit_ulp)},   {"near_bits", summary_json(s.near_bits)}};
}

target_samples samples_from(const json& j) {
    target_samples s;
    s.cases = j.at("cases").get<std::size_t>();
    s.verdicts = j.at("verdicts").get<std::array<std::size_t, verdict_kind_count>>();
    s.causes = j.at("causes").get<std::array<std::size_t, disagreement_cause_count>>();
    s.near_ulp = summary_from(j.at("near_ulp"));
    s.far_ulp = summary_from(j.at("far_ulp"));
    s.hit_ulp = summary_from(j.at("hit_ulp"));
    s.near_bits = summary_from(j.at("near_bits"));
    return s;
}

json stability_samples_json(const stability_samples& s) {
    json buckets = json::array(), near = json::array();
    for (int b = 0; b < condition_bucket_count; ++b) {
        const bucket_tally& t = s.buckets[b];
        buckets.push_back({t.cases, t.misclassified, t.disagreements, t.conditioning_limited, t.algorithmic, t.by_design});
        near.push_back(summary_json(s.near_ulp[b]));
    }
    return {{"buckets", buckets},
            {"near_ulp", near},
            {"excess", summary_json(s.excess)},
            {"counts", {s.above_line, s.well_conditioned, s.well_conditioned_above}}};
}

stability_samples stability_samples_from(const json& j) {
    stability_samples s;
    for (int b = 0; b < condition_bucket_count; ++b) {
        const json& t = j.at("buckets").at(b);
        s.buckets[b].cases = t.at(0).get<std::size_t>();
        s.buckets[b].misclassified = t.at(1).get<std::size_t>();
        s.buckets[b].disagreements = t.at(2).get<std::size_t>();
        s.buckets[b].conditioning_limited = t.at(3).get<std::size_t>();
        s.buckets[b].algorithmic = t.at(4).get<std::size_t>();
        s.buckets[b].by_design = t.at(5).get<std::size_t>();
        s.near_ulp[b] = summary_from(j.at("near_ulp").at(b));
    }
    s.excess = summary_from(j.at("excess"));
    const json& counts = j.at("counts");
    s.above_line = counts.at(0).get<std::size_t>();
    s.well_conditioned = counts.at(1).get<std::size_t>();
    s.well_conditioned_above = counts.at(2).get<std::size_t>();
    return s;
}

template <class Samples, class ToJson>
json per_target_json(const std::vector<Samples>& overall, const std::map<std::string, std::vector<Samples>>& by_family,
                     ToJson to_json) {
    json all = json::array();
    for (const Samples& s : overall) all.push_back(to_json(s));
    json families = json::object();
    for (const auto& [family, per_target] : by_family) {
        json list = json::array();
        for (const Samples& s : per_target) list.push_back(to_json(s));
        families[family] = list;
    }
    return {{"overall", all}, {"by_family", families}};
}

template <class Samples, class FromJson>
void per_target_from(const json& j, std::size_t targets, std::vector<Samples>& overall,
                     std::map<std::string, std::vector<Samples>>& by_family, FromJson from_json) {
    const auto read = [&](const json& list) {
        std::vector<Samples> out;
        for (const json& s : list) out.push_back(from_json(s));
        if (out.size() != targets) throw json::other_error::create(501, "target count differs", &j);
        return out;
    };
    overall = read(j.at("overall"));
    for (const auto& [family, list] : j.at("by_family").items()) by_family[family] = read(list);
}

invalid_reason reason_from(const json& j) {
    const std::string name = j.get<std::string>();
    for (int r = 0; r <= static_cast<int>(invalid_reason::bad_interval); ++r)
        if (name == invalid_reason_name(static_cast<invalid_reason>(r))) return static_cast<invalid_reason>(r);
    throw json::other_error::create(501, "unknown invalid reason '" + name + "'", &j);
}

}  // namespace

json targets_json(const std::vector<audit_target>& targets) {
    json out = json::array();
    for (const audit_target& t : targets) {
        out.push_back({{"variant", t.subject.name},
                       {"precision", precision_name(t.prec)},
                       {"citation", t.subject.citation},
                       {"formula", t.subject.formula},
                       {"contract", contract_json(t.subject.promises)}});
    }
    return out;
}

std::vector<audit_target> targets_from_json(const json& j) {
    std::vector<audit_target> targets;
    for (const json& t : j) {
        audit_target target;
        target.subject.name = t.at("variant").get<std::string>();
        const std::optional<precision> prec = precision_from_name(t.at("precision").get<std::string>());
        if (!prec) throw json::other_error::create(501, "unknown precision", &t.at("precision"));
        target.prec = *prec;
        target.subject.citation = t.at("citation").get<std::string>();
        target.subject.formula = t.at("formula").get<std::string>();
        target.subject.promises = contract_from_json(t.at("contract"));
        targets.push_back(std::move(target));
    }
    return targets;
}

json state_json(const audit_state& state) {
    const audit_accumulator& a = state.audit;
    json invalid_list = json::array();
    for (const invalid_case& c : a.invalid_list)
        invalid_list.push_back({c.index, c.id, c.source, invalid_reason_name(c.at_float), invalid_reason_name(c.at_double)});
    json audit = {{"cases", a.cases},
                  {"cases_by_family", a.cases_by_family},
                  {"invalid", a.invalid},
                  {"invalid_list", invalid_list}};
    audit.update(per_target_json(a.overall, a.by_family, samples_json));
    json points = json::array();
    for (const auto& [family, kept] : state.points.sample())
        for (const auto& [key, r] : kept)
            points.push_back({{"family_key", family},
                              {"hash", key.first},
                              {"index", key.second},
                              {"family", r.family},
                              {"ratio", r.ratio},
                              {"kappa_float", r.kappa_float},
                              {"kappa_double", r.kappa_double},
                              {"verdict", r.verdict},
                              {"near_ulp", r.near_ulp}});
    return {{"audit", audit},
            {"stability", per_target_json(state.stability.overall, state.stability.by_family, stability_samples_json)},
            {"case_points", points}};
}

audit_state state_from_json(const json& j, const std::vector<audit_target>& targets) {
    audit_state state(targets);
    const json& a = j.at("audit");
    state.audit.cases = a.at("cases").get<std::size_t>();
    state.audit.cases_by_family = a.at("cases_by_family").get<std::map<std::string, std::size_t>>();
    state.audit.invalid = a.at("invalid").get<std::array<std::size_t, 2>>();
    for (const json& c : a.at("invalid_list"))
        state.audit.invalid_list.push_back({c.at(1).get<std::string>(), c.at(2).get<std::string>(),
                                            reason_from(c.at(3)), reason_from(c.at(4)), c.at(0).get<std::size_t>()});
    per_target_from(a, targets.size(), state.audit.overall, state.audit.by_family, samples_from);
    per_target_from(j.at("stability"), targets.size(), state.stability.overall, state.stability.by_family,
                    stability_samples_from);
    for (const json& p : j.at("case_points")) {
        case_points::row r;
        r.index = p.at("index").get<std::size_t>();
        r.family = p.at("family");
        r.ratio = p.at("ratio");
        r.kappa_float = p.at("kappa_float");
        r.kappa_double = p.at("kappa_double");
        r.verdict = p.at("verdict").get<std::vector<json>>();
        r.near_ulp = p.at("near_ulp").get<std::vector<json>>();
        if (r.verdict.size() != targets.size() || r.near_ulp.size() != targets.size())
            throw json::other_error::create(501, "case point with a different target count", &p);
        state.points.insert(p.at("family_key").get<std::string>(),
                            {p.at("hash").get<std::uint64_t>(), r.index}, std::move(r));
    }
    return state;
}

}  // namespace rayverify
