#include "report/shard_state.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>

#include <deque>
#include <mutex>

#include "corpus/case_stream.h"
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

json double_json(double x) { return hex_float(x); }
double double_from(const json& j) { return parse_exact_double(j.get<std::string>(), "shard state", 0, "value"); }

// A histogram's buckets as one string, "key:count,Δkey:count,...", each key
// after the first as its distance from the one before: one JSON value instead
// of two arrays and two numbers per bucket, which made parsing the states
// nearly all of a merge's time.
std::string buckets_text(const error_summary::histogram_map& buckets) {
    std::string text;
    std::uint64_t previous = 0;
    for (const auto& [bucket, n] : buckets) {
        text += fmt::format("{}{}:{}", text.empty() ? "" : ",", bucket - previous, n);
        previous = bucket;
    }
    return text;
}

void buckets_from_text(const json& j, error_summary& summary) {
    const std::string& text = j.get_ref<const std::string&>();
    std::uint64_t key = 0;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t comma = std::min(text.find(',', at), text.size());
        const std::string_view pair = std::string_view(text).substr(at, comma - at);
        const std::size_t colon = pair.find(':');
        std::uint64_t step = 0;
        std::size_t n = 0;
        if (colon == std::string_view::npos || !parse_unsigned(pair.substr(0, colon), step) ||
            !parse_unsigned(pair.substr(colon + 1), n) || (at > 0 && step == 0) || key + step < key)
            throw json::other_error::create(501, fmt::format("malformed buckets at '{}'", pair), &j);
        key += step;
        summary.add_to_bucket(key, n);
        at = comma + 1;
    }
}

json summary_json(const error_summary& s) {
    return {{"count", s.count}, {"max", double_json(s.max)}, {"max_index", s.max_index}, {"max_id", s.max_id},
            {"buckets", buckets_text(s.histogram())}};
}

error_summary summary_from(const json& j) {
    error_summary s;
    s.count = j.at("count").get<std::size_t>();
    s.max = double_from(j.at("max"));
    s.max_index = j.at("max_index").get<std::size_t>();
    s.max_id = j.at("max_id").get<std::string>();
    buckets_from_text(j.at("buckets"), s);
    return s;
}

json samples_json(const target_samples& s) {
    json out = {{"cases", s.cases}, {"verdicts", s.verdicts}, {"causes", s.causes}};
    for (const error_figure_definition& f : error_figures) out[std::string(f.name)] = summary_json(s.errors[f.figure]);
    return out;
}

target_samples samples_from(const json& j) {
    target_samples s;
    s.cases = j.at("cases").get<std::size_t>();
    s.verdicts = j.at("verdicts").get<std::array<std::size_t, verdict_kind_count>>();
    s.causes = j.at("causes").get<std::array<std::size_t, disagreement_cause_count>>();
    for (const error_figure_definition& f : error_figures) s.errors[f.figure] = summary_from(j.at(std::string(f.name)));
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

// The families' tallies; the whole run's ("overall", which check_shard_state
// compares with their sums) is their merge, formed again when needed.
template <class Samples, class FromJson>
void per_target_from(const json& j, std::size_t targets, std::map<std::string, std::vector<Samples>>& by_family,
                     FromJson from_json) {
    const auto read = [&](const json& list) {
        std::vector<Samples> out;
        for (const json& s : list) out.push_back(from_json(s));
        if (out.size() != targets) throw json::other_error::create(501, "target count differs", &j);
        return out;
    };
    for (const auto& [family, list] : j.at("by_family").items()) by_family[family] = read(list);
}

invalid_reason reason_from(const json& j) {
    const std::string name = j.get<std::string>();
    for (int r = 0; r <= static_cast<int>(invalid_reason::bad_interval); ++r)
        if (name == invalid_reason_name(static_cast<invalid_reason>(r))) return static_cast<invalid_reason>(r);
    throw json::other_error::create(501, "unknown invalid reason '" + name + "'", &j);
}

// Walks a shard state document, naming every field it finds wrong by its path.
class state_checker {
public:
    state_checker(const json& doc, const std::string& file) : doc_(doc), file_(file) {}

    void run(bool header_only) {
        if (!doc_.is_object()) fail("", "is not a JSON object");
        text(member(doc_, "", "format"), "format");
        const json& shard = member(doc_, "", "shard");
        count_ = whole(member(shard, "shard", "count"), "shard.count");
        index_ = whole(member(shard, "shard", "index"), "shard.index");
        if (count_ == 0) fail("shard.count", "is 0, expected a number of shards ≥ 1");
        if (index_ == 0 || index_ > count_)
            fail("shard.index", fmt::format("is {}, expected 1 to shard.count ({})", index_, count_));
        const json& input = member(doc_, "", "input");
        total_ = whole(member(input, "input", "cases"), "input.cases");
        for (const char* list : {"paths", "generated"}) {
            const std::string path = std::string("input.") + list;
            const json& items = array(member(input, "input", list), path);
            for (std::size_t i = 0; i < items.size(); ++i) text(items[i], fmt::format("{}[{}]", path, i));
        }
        const std::string fingerprint = text(member(input, "input", "fingerprint"), "input.fingerprint");
        if (!is_fingerprint_text(fingerprint))
            fail("input.fingerprint", fmt::format("'{}' is not 16 hex digits", printable(fingerprint)));
        check_digests(member(input, "input", "digests"));
        cases_ = whole(member(shard, "shard", "cases"), "shard.cases");
        text(member(doc_, "", "command"), "command");
        if (!member(doc_, "", "build").is_object()) fail("build", "is not a JSON object");
        check_targets();
        check_per_case_file();
        if (header_only) return;
        const json& state = member(doc_, "", "state");
        check_audit(member(state, "state", "audit"));
        check_stability(member(state, "state", "stability"));
        check_points(array(member(state, "state", "case_points"), "state.case_points"));
        // Absent in a shard written before they were kept: the merged report then has none.
        if (state.contains("cases_to_open")) check_examples(array(state["cases_to_open"], "state.cases_to_open"));
        if (state.contains("contract_lint"))
            check_lint(array(state["contract_lint"], "state.contract_lint", targets_));
    }

private:
    [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
        throw input_error(file_, 0, field, problem);
    }

    const json& member(const json& j, const std::string& path, const char* key) const {
        const std::string field = path.empty() ? key : path + "." + key;
        if (!j.is_object()) fail(path, "is not a JSON object");
        const auto it = j.find(key);
        if (it == j.end()) fail(field, "is missing");
        return *it;
    }
    const json& array(const json& j, const std::string& path, std::optional<std::size_t> size = {}) const {
        if (!j.is_array()) fail(path, fmt::format("is {}, expected an array", shown(j)));
        if (size && j.size() != *size) fail(path, fmt::format("has {} entries, expected {}", j.size(), *size));
        return j;
    }
    static std::string shown(const json& j) {
        std::string text = j.dump();
        return text.size() > 60 ? text.substr(0, 60) + "…" : text;
    }
    std::uint64_t whole(const json& j, const std::string& path) const {
        if (!j.is_number_unsigned()) fail(path, fmt::format("is {}, expected a whole number ≥ 0", shown(j)));
        return j.get<std::uint64_t>();
    }
    std::string text(const json& j, const std::string& path) const {
        if (!j.is_string()) fail(path, fmt::format("is {}, expected a string", shown(j)));
        return j.get<std::string>();
    }
    // A plotted figure as optional_number writes it: a number, "inf", "-inf", "nan" or null.
    void figure(const json& j, const std::string& path) const {
        if (!number_from_json(j))
            fail(path, fmt::format("is {}, expected a number, \"inf\", \"-inf\", \"nan\" or null", shown(j)));
    }
    bool flag(const json& j, const std::string& path) const {
        if (!j.is_boolean()) fail(path, fmt::format("is {}, expected true or false", shown(j)));
        return j.get<bool>();
    }
    // An error, stored as a hex float: a number ≥ 0 (inf allowed, NaN never).
    double error_value(const json& j, const std::string& path) const {
        const std::string t = text(j, path);
        double x = 0;
        try {
            x = parse_exact_double(t, file_, 0, path);
        } catch (const input_error&) {
            fail(path, fmt::format("'{}' is not a number", printable(t)));
        }
        if (std::isnan(x) || x < 0) fail(path, fmt::format("is {}, expected an error ≥ 0 (never NaN)", t));
        return x;
    }
    // A global case index of this shard's cases.
    void case_index(std::uint64_t i, const std::string& path) const {
        if (i >= total_) fail(path, fmt::format("is {}, beyond the input's {} cases", i, total_));
        if (i % count_ != index_ - 1)
            fail(path, fmt::format("is {}, a case of shard {}/{}, not of this shard {}/{}", i, i % count_ + 1, count_,
                                   index_, count_));
    }

    void check_targets() {
        const json& list = array(member(doc_, "", "targets"), "targets");
        if (list.empty()) fail("targets", "is empty");
        targets_ = list.size();
        for (std::size_t t = 0; t < list.size(); ++t) {
            const std::string path = fmt::format("targets[{}]", t);
            const json& target = list[t];
            for (const char* key : {"variant", "citation", "formula"}) text(member(target, path, key), path + "." + key);
            const std::string precision = text(member(target, path, "precision"), path + ".precision");
            if (!precision_from_name(precision))
                fail(path + ".precision", fmt::format("'{}' is neither float nor double", printable(precision)));
            const json& c = member(target, path, "contract");
            const std::string spec = text(member(c, path + ".contract", "spec"), path + ".contract.spec");
            try {
                parse_contract(spec);
            } catch (const std::invalid_argument& e) {
                fail(path + ".contract.spec", fmt::format("'{}': {}", printable(spec), e.what()));
            }
            text(member(c, path + ".contract", "tangent_rule"), path + ".contract.tangent_rule");
            if (target.contains("library"))
            {
                for (const char* key : {"name", "version", "source"})
                    text(member(target["library"], path + ".library", key), path + ".library." + key);
                if (target["library"].contains("configuration"))
                    text(target["library"]["configuration"], path + ".library.configuration");
            }
            if (target.contains("fp_environment")) text(target["fp_environment"], path + ".fp_environment");
        }
    }

    // Relative, and inside the shard directory: merge reads nothing else.
    // The digests of the files besides the cases that decide the result: a
    // results file's (and its companion's) contents, each plugin library's.
    void check_digests(const json& digests) const {
        const auto digest = [&](const json& j, const std::string& path) {
            const std::string d = text(j, path);
            if (!is_fingerprint_text(d))
                fail(path, fmt::format("'{}' is not 16 hex digits", printable(d)));
        };
        const json& results = member(digests, "input.digests", "results");
        if (!results.is_null()) digest(results, "input.digests.results");
        const json& plugins = array(member(digests, "input.digests", "plugins"), "input.digests.plugins");
        for (std::size_t i = 0; i < plugins.size(); ++i) digest(plugins[i], fmt::format("input.digests.plugins[{}]", i));
    }

    void check_per_case_file() const {
        const json& recorded = member(doc_, "", "per_case_file");
        if (recorded.is_null()) return;
        const std::filesystem::path path(text(recorded, "per_case_file"));
        const bool inside = !path.empty() && path.is_relative() && !path.has_root_name() &&
                            std::none_of(path.begin(), path.end(), [](const auto& part) { return part == ".."; });
        if (!inside)
            fail("per_case_file", fmt::format("'{}' is not a path inside the shard directory", printable(path.string())));
        // The digest of the per-case file's contents as the audit wrote them.
        const std::string digest = text(member(doc_, "", "per_case_digest"), "per_case_digest");
        if (!is_fingerprint_text(digest))
            fail("per_case_digest", fmt::format("'{}' is not 16 hex digits", printable(digest)));
    }

    // An error_summary; returns its count.
    std::uint64_t summary(const json& j, const std::string& path) const {
        const std::uint64_t n = whole(member(j, path, "count"), path + ".count");
        const double max = error_value(member(j, path, "max"), path + ".max");
        const std::uint64_t max_index = whole(member(j, path, "max_index"), path + ".max_index");
        const std::string max_id = text(member(j, path, "max_id"), path + ".max_id");
        // Format 2: the buckets as one string (buckets_text), each key its distance from the one before.
        error_summary read;
        const json& text_of_buckets = member(j, path, "buckets");
        if (!text_of_buckets.is_string()) fail(path + ".buckets", "is not a string of key:count pairs");
        try {
            buckets_from_text(text_of_buckets, read);
        } catch (const json::exception&) {
            fail(path + ".buckets", "is not a list of key:count pairs, each key after the first above the one before");
        }
        std::uint64_t in_buckets = 0, last = 0;
        constexpr double infinity = std::numeric_limits<double>::infinity();
        for (const auto& [key, size] : read.histogram()) {
            const std::string at = fmt::format("{}.buckets (key {})", path, key);
            if (key > error_summary::bucket_of(infinity))
                fail(at, fmt::format("is beyond the last bucket ({}, infinity)", error_summary::bucket_of(infinity)));
            if (size == 0) fail(at, "holds 0 errors: an empty bucket is not stored");
            if (in_buckets + size < in_buckets) fail(at, "overflows the count");
            in_buckets += size;
            last = key;
        }
        if (in_buckets != n)
            fail(path + ".count", fmt::format("is {}, but its buckets hold {} errors", n, in_buckets));
        if (n == 0 && (max != 0 || max_index != 0 || !max_id.empty()))
            fail(path + ".max", "is set although the summary holds no error");
        if (n > 0) {
            case_index(max_index, path + ".max_index");
            if (error_summary::bucket_of(max) != last)
                fail(path + ".max", fmt::format("is {}, not in the summary's last bucket (the maximum must be the "
                                                "largest error)",
                                                hex_float(max)));
        }
        return n;
    }

    // Figures of one target over some cases; its verdict and cause counts go to `sums` (the whole run's error
    // figures are checked against the families' merge, field by field, in check_audit).
    struct sample_sums {
        std::array<std::uint64_t, verdict_kind_count> verdicts{};
        std::array<std::uint64_t, disagreement_cause_count> causes{};
    };
    sample_sums samples(const json& j, const std::string& path, std::uint64_t cases) const {
        sample_sums sums;
        const std::uint64_t n = whole(member(j, path, "cases"), path + ".cases");
        if (n != cases) fail(path + ".cases", fmt::format("is {}, expected {}", n, cases));
        const json& verdicts = array(member(j, path, "verdicts"), path + ".verdicts", verdict_kind_count);
        std::uint64_t total = 0;
        for (int k = 0; k < verdict_kind_count; ++k) {
            sums.verdicts[k] =
                whole(verdicts[k], fmt::format("{}.verdicts[{}] ({})", path, k, verdict_name(static_cast<verdict_kind>(k))));
            total += sums.verdicts[k];
        }
        if (total != n)
            fail(path + ".verdicts", fmt::format("add up to {}, but the target has {} cases", total, n));
        const json& causes = array(member(j, path, "causes"), path + ".causes", disagreement_cause_count);
        std::uint64_t caused = 0, disagreeing = 0;
        for (int c = 0; c < disagreement_cause_count; ++c) {
            sums.causes[c] = whole(causes[c], fmt::format("{}.causes[{}] ({})", path, c,
                                                          cause_name(static_cast<disagreement_cause>(c))));
            caused += sums.causes[c];
        }
        for (int k = 0; k < verdict_kind_count; ++k)
            if (is_disagreement(static_cast<verdict_kind>(k))) disagreeing += sums.verdicts[k];
        if (caused != disagreeing)
            fail(path + ".causes", fmt::format("add up to {}, but the target has {} disagreements", caused, disagreeing));
        const std::uint64_t agreeing = sums.verdicts[static_cast<int>(verdict_kind::agree)];
        for (const error_figure_definition& f : error_figures) {
            const std::string name(f.name), at = path + "." + name;
            const std::uint64_t n_errors = summary(member(j, path, name.c_str()), at);
            if (n_errors > agreeing)
                fail(at + ".count", fmt::format("is {}, more than the {} agreeing cases", n_errors, agreeing));
        }
        return sums;
    }

    void check_audit(const json& a) {
        const std::uint64_t cases = whole(member(a, "state.audit", "cases"), "state.audit.cases");
        if (cases != cases_) fail("state.audit.cases", fmt::format("is {}, but shard.cases is {}", cases, cases_));
        const json& by_family_cases = member(a, "state.audit", "cases_by_family");
        if (!by_family_cases.is_object()) fail("state.audit.cases_by_family", "is not a JSON object");
        std::uint64_t family_total = 0;
        for (const auto& [family, n] : by_family_cases.items()) {
            family_cases_[family] = whole(n, "state.audit.cases_by_family." + printable(family));
            family_total += family_cases_[family];
        }
        if (family_total != cases)
            fail("state.audit.cases_by_family", fmt::format("add up to {}, but the shard has {} cases", family_total, cases));
        const json& invalid = array(member(a, "state.audit", "invalid"), "state.audit.invalid", 2);
        const std::uint64_t invalid_float = whole(invalid[0], "state.audit.invalid[0]"),
                            invalid_double = whole(invalid[1], "state.audit.invalid[1]");
        const json& list = array(member(a, "state.audit", "invalid_list"), "state.audit.invalid_list");
        std::uint64_t listed_float = 0, listed_double = 0, previous = 0;
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string at = fmt::format("state.audit.invalid_list[{}]", i);
            const json& entry = array(list[i], at, 5);
            const std::uint64_t index = whole(entry[0], at + "[0]");
            case_index(index, at + "[0]");
            if (i > 0 && index <= previous) fail(at + "[0]", "is not above the index before it");
            previous = index;
            text(entry[1], at + "[1]");
            text(entry[2], at + "[2]");
            for (int p = 0; p < 2; ++p) {
                const std::string reason = text(entry[3 + p], fmt::format("{}[{}]", at, 3 + p));
                bool known = false;
                for (int r = 0; r <= static_cast<int>(invalid_reason::bad_interval); ++r)
                    known = known || reason == invalid_reason_name(static_cast<invalid_reason>(r));
                if (!known) fail(fmt::format("{}[{}]", at, 3 + p), fmt::format("unknown reason '{}'", printable(reason)));
                if (reason != invalid_reason_name(invalid_reason::none)) ++(p == 0 ? listed_float : listed_double);
            }
        }
        if (invalid_float != listed_float)
            fail("state.audit.invalid[0]", fmt::format("is {}, but invalid_list holds {} cases invalid in float",
                                                       invalid_float, listed_float));
        if (invalid_double != listed_double)
            fail("state.audit.invalid[1]", fmt::format("is {}, but invalid_list holds {} cases invalid in double",
                                                       invalid_double, listed_double));

        const json& overall = array(member(a, "state.audit", "overall"), "state.audit.overall", targets_);
        std::vector<sample_sums> whole_run;
        for (std::size_t t = 0; t < targets_; ++t)
            whole_run.push_back(samples(overall[t], fmt::format("state.audit.overall[{}]", t), cases));
        const json& families = member(a, "state.audit", "by_family");
        if (!families.is_object()) fail("state.audit.by_family", "is not a JSON object");
        std::vector<sample_sums> summed(targets_);
        for (const auto& [family, list_of_targets] : families.items()) {
            const std::string path = "state.audit.by_family." + printable(family);
            const auto known = family_cases_.find(family);
            if (known == family_cases_.end()) fail(path, "is a family not in state.audit.cases_by_family");
            array(list_of_targets, path, targets_);
            for (std::size_t t = 0; t < targets_; ++t) {
                const sample_sums s = samples(list_of_targets[t], fmt::format("{}[{}]", path, t), known->second);
                for (int k = 0; k < verdict_kind_count; ++k) summed[t].verdicts[k] += s.verdicts[k];
                for (int c = 0; c < disagreement_cause_count; ++c) summed[t].causes[c] += s.causes[c];
            }
        }
        if (families.size() != family_cases_.size())
            fail("state.audit.by_family", "lacks a family of state.audit.cases_by_family");
        // The whole run's figures are the families' merge, field by field: a
        // reader forms them again from the families, so an edited overall
        // value would otherwise pass unnoticed.
        for (std::size_t t = 0; t < targets_; ++t) {
            target_samples merged;
            for (const auto& [family, list_of_targets] : families.items()) merged.merge(samples_from(list_of_targets[t]));
            const json expected = samples_json(merged);
            for (const error_figure_definition& f : error_figures) {
                const std::string name(f.name);
                const json& stored = overall[t][name];
                for (const auto& [key, value] : expected[name].items())
                    if (stored[key] != value)
                        fail(fmt::format("state.audit.overall[{}].{}.{}", t, name, key),
                             fmt::format("is {}, but the families' figures merge to {}", shown(stored[key]), shown(value)));
            }
        }
        for (std::size_t t = 0; t < targets_; ++t) {
            if (summed[t].verdicts != whole_run[t].verdicts)
                fail(fmt::format("state.audit.overall[{}].verdicts", t), "differ from the sums over the families");
            if (summed[t].causes != whole_run[t].causes)
                fail(fmt::format("state.audit.overall[{}].causes", t), "differ from the sums over the families");
        }
    }

    void stability_samples(const json& j, const std::string& path) const {
        const json& buckets = array(member(j, path, "buckets"), path + ".buckets", condition_bucket_count);
        const json& near = array(member(j, path, "near_ulp"), path + ".near_ulp", condition_bucket_count);
        std::uint64_t scored = 0;
        for (int b = 0; b < condition_bucket_count; ++b) {
            const std::string at = fmt::format("{}.buckets[{}]", path, b);
            const json& tally = array(buckets[b], at, 6);
            std::uint64_t v[6];
            for (int i = 0; i < 6; ++i) v[i] = whole(tally[i], fmt::format("{}[{}]", at, i));
            // cases, misclassified, disagreements, conditioning_limited, algorithmic, by_design
            if (v[1] > v[2] || v[2] > v[0] || v[3] + v[4] + v[5] != v[2])
                fail(at, "is inconsistent: expected misclassified ≤ disagreements ≤ cases and the three causes "
                         "(conditioning-limited, algorithmic, by design) adding up to the disagreements");
            if (summary(near[b], fmt::format("{}.near_ulp[{}]", path, b)) > v[0] - v[2])
                fail(fmt::format("{}.near_ulp[{}].count", path, b), "is more than the bucket's agreeing cases");
            scored += v[0];
        }
        if (scored > cases_) fail(path + ".buckets", fmt::format("hold {} cases, the shard has {}", scored, cases_));
        const std::uint64_t judged = summary(member(j, path, "excess"), path + ".excess");
        const json& counts = array(member(j, path, "counts"), path + ".counts", 3);
        const std::uint64_t above = whole(counts[0], path + ".counts[0]"), well = whole(counts[1], path + ".counts[1]"),
                            well_above = whole(counts[2], path + ".counts[2]");
        if (above > judged || well > judged || well_above > std::min(above, well))
            fail(path + ".counts", "are inconsistent with each other and with excess.count");
    }

    void check_stability(const json& st) {
        const json& overall = array(member(st, "state.stability", "overall"), "state.stability.overall", targets_);
        for (std::size_t t = 0; t < targets_; ++t) stability_samples(overall[t], fmt::format("state.stability.overall[{}]", t));
        const json& families = member(st, "state.stability", "by_family");
        if (!families.is_object()) fail("state.stability.by_family", "is not a JSON object");
        for (const auto& [family, list] : families.items()) {
            const std::string path = "state.stability.by_family." + printable(family);
            if (!family_cases_.count(family)) fail(path, "is a family not in state.audit.cases_by_family");
            array(list, path, targets_);
            for (std::size_t t = 0; t < targets_; ++t) stability_samples(list[t], fmt::format("{}[{}]", path, t));
        }
    }

    void check_points(const json& points) const {
        std::map<std::string, std::size_t> per_family;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const std::string at = fmt::format("state.case_points[{}]", i);
            const json& p = points[i];
            const std::string family = text(member(p, at, "family_key"), at + ".family_key");
            if (!family_cases_.count(family.empty() ? "-" : family))  // the audit counts an unnamed family as "-"
                fail(at + ".family_key", fmt::format("'{}' is not a family of the shard", printable(family)));
            if (++per_family[family] > case_points::per_family)
                fail(at, fmt::format("is one more than the {} points a family keeps", case_points::per_family));
            whole(member(p, at, "hash"), at + ".hash");
            case_index(whole(member(p, at, "index"), at + ".index"), at + ".index");
            text(member(p, at, "family"), at + ".family");
            for (const char* key : {"ratio", "kappa_float", "kappa_double"}) figure(member(p, at, key), at + "." + key);
            const json& verdicts = array(member(p, at, "verdict"), at + ".verdict", targets_);
            for (std::size_t t = 0; t < targets_; ++t) {
                const std::string path = fmt::format("{}.verdict[{}]", at, t);
                const std::string name = text(verdicts[t], path);
                if (!verdict_from_name(name)) fail(path, fmt::format("'{}' is not a verdict", printable(name)));
            }
            const json& near = array(member(p, at, "near_ulp"), at + ".near_ulp", targets_);
            for (std::size_t t = 0; t < targets_; ++t) figure(near[t], fmt::format("{}.near_ulp[{}]", at, t));
        }
    }

    void check_examples(const json& list) const {
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string at = fmt::format("state.cases_to_open[{}]", i);
            const json& e = list[i];
            if (whole(member(e, at, "target"), at + ".target") >= targets_)
                fail(at + ".target", fmt::format("is beyond the {} targets", targets_));
            const std::string kind = text(member(e, at, "kind"), at + ".kind");
            if (kind != "first" && kind != "worst" && kind != "farthest")
                fail(at + ".kind", fmt::format("'{}' is not first, worst or farthest", printable(kind)));
            const std::string verdict = text(member(e, at, "verdict"), at + ".verdict");
            if (!verdict_from_name(verdict)) fail(at + ".verdict", fmt::format("'{}' is not a verdict", printable(verdict)));
            case_index(whole(member(e, at, "index"), at + ".index"), at + ".index");
            error_value(member(e, at, "error"), at + ".error");
            text(member(e, at, "line"), at + ".line");
            text(member(e, at, "source"), at + ".source");
            const json& cause = member(e, at, "cause");
            if (!cause.is_null() && !cause_from_name(text(cause, at + ".cause")))
                fail(at + ".cause", fmt::format("'{}' is not a cause", printable(cause.get<std::string>())));
        }
    }

    void check_lint(const json& list) const {
        for (std::size_t t = 0; t < list.size(); ++t) {
            const std::string at = fmt::format("state.contract_lint[{}]", t);
            const std::uint64_t scored = whole(member(list[t], at, "scored"), at + ".scored");
            const std::uint64_t wrong = whole(member(list[t], at, "wrong"), at + ".wrong");
            if (wrong > scored) fail(at + ".wrong", "is more than the cases scored");
            const json& fixed = array(member(list[t], at, "fixed"), at + ".fixed");
            const json& broken = array(member(list[t], at, "broken"), at + ".broken", fixed.size());
            for (std::size_t k = 0; k < fixed.size(); ++k) {
                if (whole(fixed[k], fmt::format("{}.fixed[{}]", at, k)) > wrong)
                    fail(fmt::format("{}.fixed[{}]", at, k), "is more than the disagreements");
                if (whole(broken[k], fmt::format("{}.broken[{}]", at, k)) > scored - wrong)
                    fail(fmt::format("{}.broken[{}]", at, k), "is more than the agreeing cases");
            }
        }
    }

    const json& doc_;
    const std::string& file_;
    std::uint64_t count_ = 1, index_ = 1, total_ = 0, cases_ = 0;
    std::size_t targets_ = 0;
    std::map<std::string, std::uint64_t> family_cases_;
};

}  // namespace

void check_shard_state(const json& doc, const std::string& file, bool header_only) {
    state_checker(doc, file).run(header_only);
}

json targets_json(const std::vector<audit_target>& targets) {
    json out = json::array();
    for (const audit_target& t : targets) {
        out.push_back({{"variant", t.subject.name},
                       {"precision", precision_name(t.prec)},
                       {"citation", t.subject.citation},
                       {"formula", t.subject.formula},
                       {"contract", contract_json(t.subject.promises)}});
        if (t.subject.library) out.back()["library"] = library_json(*t.subject.library);
        if (!t.subject.fp_environment.empty()) out.back()["fp_environment"] = t.subject.fp_environment;
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
        if (t.contains("library"))
            target.subject.library = library_identity{t["library"].at("name").get<std::string>(),
                                                      t["library"].at("version").get<std::string>(),
                                                      t["library"].at("source").get<std::string>(),
                                                      t["library"].value("configuration", std::string())};
        target.subject.fp_environment = t.value("fp_environment", std::string());
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
    audit.update(per_target_json(a.overall(), a.by_family, samples_json));
    json points = json::array();
    for (const auto& [family, kept] : state.points.sample())
        for (const auto& [key, r] : kept) {
            json verdict_names = json::array(), near_ulp = json::array();
            for (verdict_kind v : r.verdict) verdict_names.push_back(verdict_name(v));
            for (const std::optional<double>& ulp : r.near_ulp) near_ulp.push_back(optional_number(ulp));
            points.push_back({{"family_key", family},
                              {"hash", key.first},
                              {"index", key.second},
                              {"family", r.family},
                              {"ratio", optional_number(r.ratio)},
                              {"kappa_float", optional_number(r.kappa_float)},
                              {"kappa_double", optional_number(r.kappa_double)},
                              {"verdict", verdict_names},
                              {"near_ulp", near_ulp}});
        }
    json examples = json::array();
    const auto example = [&](std::size_t t, const char* kind, verdict_kind v, const case_example& e) {
        examples.push_back({{"target", t},
                            {"kind", kind},
                            {"verdict", verdict_name(v)},
                            {"index", e.index},
                            {"error", double_json(e.error)},
                            {"line", format_case_line(e.kase)},
                            {"source", e.kase.source},
                            {"cause", e.cause ? json(cause_name(*e.cause)) : json(nullptr)}});
    };
    for (std::size_t t = 0; t < state.examples.first.size(); ++t) {
        for (int k = 0; k < verdict_kind_count; ++k)
            for (const case_example& e : state.examples.first[t][k]) example(t, "first", static_cast<verdict_kind>(k), e);
        for (int k = 0; k < verdict_kind_count; ++k)
            for (const case_example& e : state.examples.worst[t][k]) example(t, "worst", static_cast<verdict_kind>(k), e);
        for (const case_example& e : state.examples.farthest[t]) example(t, "farthest", verdict_kind::agree, e);
    }
    json lint = json::array();
    for (const contract_lint_tally& tally : state.lint.tallies)
        lint.push_back({{"scored", tally.scored}, {"wrong", tally.wrong}, {"fixed", tally.fixed}, {"broken", tally.broken}});
    return {{"audit", audit},
            {"stability", per_target_json(state.stability.overall(), state.stability.by_family, stability_samples_json)},
            {"case_points", points},
            {"cases_to_open", examples},
            {"contract_lint", lint}};
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
    per_target_from(a, targets.size(), state.audit.by_family, samples_from);
    per_target_from(j.at("stability"), targets.size(), state.stability.by_family,
                    stability_samples_from);
    for (const json& p : j.at("case_points")) {
        case_points::row r;
        r.index = p.at("index").get<std::size_t>();
        // Checked by check_shard_state; a value that is not what it checks fails here too.
        const auto number = [&p](const json& j, const char* what) {
            const std::optional<std::optional<double>> x = number_from_json(j);
            if (!x) throw json::other_error::create(501, fmt::format("case point's {} is not a number", what), &p);
            return *x;
        };
        r.family = p.at("family").get<std::string>();
        r.ratio = number(p.at("ratio"), "ratio");
        r.kappa_float = number(p.at("kappa_float"), "kappa_float");
        r.kappa_double = number(p.at("kappa_double"), "kappa_double");
        const json& verdicts = p.at("verdict");
        const json& near = p.at("near_ulp");
        if (verdicts.size() != targets.size() || near.size() != targets.size())
            throw json::other_error::create(501, "case point with a different target count", &p);
        for (const json& v : verdicts) {
            const std::optional<verdict_kind> kind = verdict_from_name(v.get<std::string>());
            if (!kind) throw json::other_error::create(501, "case point with an unknown verdict", &p);
            r.verdict.push_back(*kind);
        }
        for (const json& ulp : near) r.near_ulp.push_back(number(ulp, "near_ulp"));
        state.points.insert(p.at("family_key").get<std::string>(),
                            {p.at("hash").get<std::uint64_t>(), r.index}, std::move(r));
    }
    if (j.contains("cases_to_open"))
        for (const json& e : j.at("cases_to_open")) {
            case_example example;
            example.index = e.at("index").get<std::size_t>();
            example.error = double_from(e.at("error"));
            std::vector<corpus_case> parsed;
            try {
                parsed = parse_corpus(e.at("source").get<std::string>(), e.at("line").get<std::string>(), false);
            } catch (const input_error& problem) {
                throw json::other_error::create(501, problem.what(), &e);
            }
            if (parsed.size() != 1) throw json::other_error::create(501, "a case to open is not one corpus line", &e);
            example.kase = std::move(parsed[0]);
            example.kase.source = e.at("source").get<std::string>();
            if (!e.at("cause").is_null()) example.cause = cause_from_name(e.at("cause").get<std::string>());
            const std::size_t t = e.at("target").get<std::size_t>();
            if (t >= targets.size()) throw json::other_error::create(501, "a case to open of no target", &e);
            if (e.at("kind") == "first" || e.at("kind") == "worst") {
                const std::optional<verdict_kind> v = verdict_from_name(e.at("verdict").get<std::string>());
                if (!v) throw json::other_error::create(501, "a case to open with an unknown verdict", &e);
                auto& lists = e.at("kind") == "first" ? state.examples.first : state.examples.worst;
                lists[t][static_cast<int>(*v)].push_back(std::move(example));
            } else {
                state.examples.farthest[t].push_back(std::move(example));
            }
        }
    if (j.contains("contract_lint")) {
        const json& lint = j.at("contract_lint");
        for (std::size_t t = 0; t < targets.size() && t < lint.size(); ++t) {
            contract_lint_tally& tally = state.lint.tallies[t];
            tally.scored = lint[t].at("scored").get<std::size_t>();
            tally.wrong = lint[t].at("wrong").get<std::size_t>();
            tally.fixed = lint[t].at("fixed").get<std::vector<std::size_t>>();
            tally.broken = lint[t].at("broken").get<std::vector<std::size_t>>();
        }
    }
    return state;
}

}  // namespace rayverify
