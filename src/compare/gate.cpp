#include "compare/gate.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <utility>

#include "compare/audit.h"
#include "core/contract.h"
#include "core/input_error.h"
#include "core/text_lines.h"

namespace rayverify {
namespace {

// The figures in baseline order: the case count, the scored cases, each
// disagreement verdict (judge.h's names, in verdict order), then the ULP figures.
const std::vector<std::string_view>& figure_list() {
    static const std::vector<std::string_view> list = [] {
        std::vector<std::string_view> names = {"cases", scored_figure};
        for (int k = 0; k < verdict_kind_count; ++k)
            if (is_disagreement(static_cast<verdict_kind>(k))) names.push_back(verdict_name(static_cast<verdict_kind>(k)));
        static const std::vector<std::string> gated = [] {
            std::vector<std::string> out;
            for (const error_figure_definition& f : error_figures)
                if (f.gated)
                    for (const char* statistic : {"_max", "_p99"}) out.push_back(std::string(f.case_name) + statistic);
            return out;
        }();
        names.insert(names.end(), gated.begin(), gated.end());
        return names;
    }();
    return list;
}

std::size_t figure_index(std::string_view figure) {
    const auto& list = figure_list();
    return static_cast<std::size_t>(std::find(list.begin(), list.end(), figure) - list.begin());
}

constexpr std::string_view format_line = "rayverify-baseline 1";

std::string variant_of(const std::string& target) { return target.substr(0, target.find('/')); }

std::string quoted(std::string_view token) { return "'" + printable(token) + "'"; }

std::string number_text(double x) {
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    return fmt::format("{}", x);  // shortest round trip
}

}  // namespace

std::span<const std::string_view> figure_names() { return figure_list(); }

bool is_ulp_figure(std::string_view figure) { return figure.find("_ulp_") != std::string_view::npos; }

bool figure_key::operator<(const figure_key& other) const {
    if (target != other.target) return target < other.target;
    const bool whole = family == all_families, other_whole = other.family == all_families;
    if (whole != other_whole) return whole;
    if (family != other.family) return family < other.family;
    const std::size_t a = figure_index(figure), b = figure_index(other.figure);
    return a != b ? a < b : figure < other.figure;
}

std::string figure_key::text() const { return target + " " + family + " " + figure; }

figure_table figures_of(const audit_totals& totals) {
    figure_table table;
    const auto add = [&](const std::string& target, const std::string& family, const target_tally& t) {
        table[{target, family, "cases"}] = static_cast<double>(t.cases);
        table[{target, family, std::string(scored_figure)}] = static_cast<double>(t.scored());
        for (int k = 0; k < verdict_kind_count; ++k) {
            const auto kind = static_cast<verdict_kind>(k);
            if (is_disagreement(kind))
                table[{target, family, std::string(verdict_name(kind))}] = static_cast<double>(t.verdicts[k]);
        }
        for (const error_figure_definition& f : error_figures) {
            const error_statistics& s = t.errors[f.figure];
            if (!f.gated || s.count == 0) continue;
            // The gate compares the figures as printed (a baseline's and this run's).
            table[{target, family, std::string(f.case_name) + "_max"}] = printed_figure(s.max);
            table[{target, family, std::string(f.case_name) + "_p99"}] = printed_figure(s.p99);
        }
    };
    for (std::size_t i = 0; i < totals.targets.size(); ++i) {
        const std::string target = totals.targets[i].label();
        add(target, std::string(all_families), totals.overall[i]);
        for (const auto& [family, tallies] : totals.by_family) add(target, family, tallies[i]);
    }
    return table;
}

gate_policy baseline::policy_for(const std::string& target) const {
    gate_policy policy;
    const std::string variant = variant_of(target);
    // Least specific first, so that the most specific line wins.
    for (const std::string& scope : {std::string("default"), variant, target}) {
        for (const policy_line& p : policies) {
            if (p.scope != scope) continue;
            (p.key == "ulp_slack" ? policy.ulp_slack : policy.count_slack) = p.value;
        }
    }
    return policy;
}

baseline parse_baseline(const std::string& file, std::string_view text) {
    baseline b;
    std::vector<std::string> pending;  // comment lines waiting for their entry
    bool seen_format = false;
    // Lines as every text reader takes them (core/text_lines.h): a carriage
    // return, NUL byte or invalid UTF-8 inside a line is refused, so that what
    // --update writes back reads as the same lines.
    for_each_text_line(file, text, [&](std::size_t line_number, std::string_view line) {
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos) return;
        if (line[first] == '#') {
            pending.emplace_back(line.substr(first));
            return;
        }
        std::vector<std::string> words;
        {
            std::size_t at = 0;
            // A `#` token ends the entry: what follows is a comment on the same line (not kept).
            while ((at = line.find_first_not_of(" \t", at)) != std::string::npos && line[at] != '#') {
                const std::size_t stop = std::min(line.find_first_of(" \t", at), line.size());
                words.emplace_back(line.substr(at, stop - at));
                at = stop;
            }
        }
        const auto error = [&](const std::string& field, const std::string& problem) {
            return input_error(file, line_number, field, problem);
        };
        const auto number = [&](const std::string& token, const std::string& field) {
            if (token == "inf") return std::numeric_limits<double>::infinity();
            double value = 0;
            const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
            if (ec != std::errc() || ptr != token.data() + token.size() || std::isnan(value) || value < 0)
                throw error(field, fmt::format("{} is not a number ≥ 0 (decimal or inf)", quoted(token)));
            return value;
        };
        if (!seen_format) {
            // Compared word by word: trailing blanks and a `#` comment are allowed as on any line.
            if (words.size() == 2 && words[0] == "rayverify-baseline" && words[1] != "1")
                throw error("format", fmt::format("baseline format version {}; this rayverify reads version 1",
                                                  quoted(words[1])));
            if (words != std::vector<std::string>{"rayverify-baseline", "1"})
                throw error("format", fmt::format("the first entry must be '{}' (is this a rayverify gate baseline?)",
                                                  format_line));
            seen_format = true;
            b.format_comments = std::exchange(pending, {});
            return;
        }
        // A count (of cases, of disagreements, count_slack) is a whole number: inf would pass any count.
        const auto count = [&](const std::string& token, const std::string& field, const std::string& what) {
            const double value = number(token, field);
            if (!std::isfinite(value) || value != std::floor(value) || value > 0x1p53)
                throw error(field, fmt::format("{} is a whole number of cases, got {}", what, quoted(token)));
            return value;
        };
        // A target's precision, when the text names a target ("naive/float").
        const auto check_precision = [&](const std::string& target, const std::string& field) {
            const std::string precision = target.substr(target.find('/') + 1);
            if (!precision_from_name(precision))
                throw error(field, fmt::format("{}: unknown precision {} (float or double)", quoted(target),
                                               quoted(precision)));
        };
        if (words[0] == "policy") {
            if (words.size() != 4) throw error("policy", "expected 'policy SCOPE ulp_slack|count_slack VALUE'");
            if (words[2] != "ulp_slack" && words[2] != "count_slack")
                throw error("policy",
                            fmt::format("unknown policy key {} (ulp_slack or count_slack)", quoted(words[2])));
            if (words[1].find('/') != std::string::npos) check_precision(words[1], "policy");
            const double value =
                words[2] == "count_slack" ? count(words[3], "value", "count_slack") : number(words[3], "value");
            if (words[2] == "ulp_slack" && !(value >= 1 && std::isfinite(value)))
                throw error("value", "ulp_slack is a factor ≥ 1");
            for (const policy_line& p : b.policies)
                if (p.scope == words[1] && p.key == words[2])
                    throw error("policy", fmt::format("duplicate policy line for {} {} (the gate would use one of "
                                                      "them silently)",
                                                      printable(words[1]), words[2]));
            b.policies.push_back({words[1], words[2], value, std::exchange(pending, {})});
            return;
        }
        if (words[0] == "allow-missing") {
            if (words.size() != 2) throw error("allow-missing", "expected 'allow-missing FAMILY|VARIANT|TARGET'");
            b.allowed_missing.emplace_back(words[1], std::exchange(pending, {}));
            return;
        }
        if (words[0] == "library") {
            if (words.size() < 3) throw error("library", "expected 'library VARIANT SET-UP'");
            if (words[1].find('/') != std::string::npos)
                throw error("library", fmt::format("{} is a target; a library line names a variant, like embree3",
                                                   quoted(words[1])));
            std::string text = words[2];
            for (std::size_t i = 3; i < words.size(); ++i) text += " " + words[i];
            if (!b.configurations.emplace(words[1], configuration_line{text, std::exchange(pending, {})}).second)
                throw error("library", fmt::format("duplicate library line for {}", printable(words[1])));
            return;
        }
        if (words[0] == "contract") {
            if (words.size() != 3) throw error("contract", "expected 'contract VARIANT SPEC'");
            if (words[1].find('/') != std::string::npos)
                throw error("contract", fmt::format("{} is a target; a contract line names a variant, like naive",
                                                    quoted(words[1])));
            std::string spec;
            try {
                spec = format_contract(parse_contract(words[2]));
            } catch (const std::invalid_argument& e) {
                throw error("contract", e.what());
            }
            if (!b.contracts.emplace(words[1], configuration_line{spec, std::exchange(pending, {})}).second)
                throw error("contract", fmt::format("duplicate contract line for {}", printable(words[1])));
            return;
        }
        if (words.size() != 4) throw error("entry", fmt::format("expected 'TARGET FAMILY FIGURE VALUE', got {} fields",
                                                                words.size()));
        if (words[0].find('/') == std::string::npos)
            throw error("target", fmt::format("{} is not a target like naive/float", quoted(words[0])));
        check_precision(words[0], "target");
        if (figure_index(words[2]) == figure_list().size())
            throw error("figure", fmt::format("unknown figure {}", quoted(words[2])));
        // A ULP figure as printed: a baseline written with more digits (before
        // figures were printed to figure_significant_digits) compares alike.
        const double value = is_ulp_figure(words[2]) ? printed_figure(number(words[3], "value"))
                                                     : count(words[3], "value", words[2]);
        figure_key key{words[0], words[1], words[2]};
        if (!b.figures.emplace(key, value).second)
            throw error("entry", fmt::format("duplicate entry for {}", printable(key.text())));
        if (!pending.empty()) b.comments[key] = std::exchange(pending, {});
    });
    if (!seen_format) throw input_error(file, 0, "format", fmt::format("empty baseline: no '{}' line", format_line));
    b.trailing_comments = std::move(pending);
    return b;
}

std::string format_baseline(const baseline& b) {
    std::string out;
    const auto comments = [&](const std::vector<std::string>& lines) {
        for (const std::string& c : lines) out += c + "\n";
    };
    comments(b.format_comments);
    out += std::string(format_line) + "\n";
    for (const policy_line& p : b.policies) {
        comments(p.comments);
        out += fmt::format("policy {} {} {}\n", p.scope, p.key, number_text(p.value));
    }
    for (const auto& [variant, line] : b.configurations) {
        comments(line.comments);
        out += fmt::format("library {} {}\n", variant, line.text);
    }
    for (const auto& [variant, line] : b.contracts) {
        comments(line.comments);
        out += fmt::format("contract {} {}\n", variant, line.text);
    }
    for (const auto& [name, lines] : b.allowed_missing) {
        comments(lines);
        out += fmt::format("allow-missing {}\n", name);
    }
    std::string previous;
    for (const auto& [key, value] : b.figures) {
        if (key.target + key.family != previous) out += "\n";
        previous = key.target + key.family;
        if (auto it = b.comments.find(key); it != b.comments.end()) comments(it->second);
        out += fmt::format("{} {}\n", key.text(), number_text(value));
    }
    if (!b.trailing_comments.empty()) out += "\n";
    comments(b.trailing_comments);
    return out;
}

baseline new_baseline() {
    baseline b;
    b.format_comments = {
        "# rayverify gate baseline: the audit figures a change may not make worse.",
        "# One entry a line: TARGET FAMILY FIGURE VALUE (FAMILY 'all' is the whole corpus).",
        "# Counts are cases with that verdict ('scored': the cases judged, fewer is worse); *_ulp_max",
        "# and *_ulp_p99 are the nearest (near_) and far root's error in ULPs over the agreeing",
        "# cases. Regenerate with `rayverify gate --baseline FILE --update`; `#` lines stay with",
        "# the entry below them."};
    b.policies = {{"default", "ulp_slack", 1, {"# A ULP figure may grow to baseline × ulp_slack, a count by count_slack cases;",
                                               "# add 'policy VARIANT|TARGET KEY VALUE' lines to override per variant."}},
                  {"default", "count_slack", 0, {}}};
    return b;
}

configuration_table configurations_of(std::span<const audit_target> targets) {
    configuration_table out;
    for (const audit_target& t : targets)
        if (t.subject.library && !t.subject.library->configuration.empty())
            out[t.subject.name] = t.subject.library->configuration;
    return out;
}

std::string_view setup_aspect_name(setup_aspect aspect) {
    return aspect == setup_aspect::contract ? "contract" : "library set-up";
}

configuration_table contracts_of(std::span<const audit_target> targets) {
    configuration_table out;
    for (const audit_target& t : targets) out[t.subject.name] = format_contract(t.subject.promises);
    return out;
}

baseline updated_baseline(const baseline& old, const figure_table& current,
                          const configuration_table& current_configurations,
                          const configuration_table& current_contracts) {
    baseline b = old;
    std::set<std::string> run;
    for (const auto& entry : current) run.insert(entry.first.target);
    for (const std::string& target : run) {
        const std::string variant = variant_of(target);
        if (const auto judged_by = current_contracts.find(variant); judged_by != current_contracts.end())
            b.contracts[variant].text = judged_by->second;
        const auto now = current_configurations.find(variant);
        if (now == current_configurations.end()) {
            if (const auto gone = b.configurations.find(variant); gone != b.configurations.end()) {
                b.trailing_comments.insert(b.trailing_comments.end(), gone->second.comments.begin(),
                                           gone->second.comments.end());
                b.configurations.erase(gone);
            }
            continue;
        }
        configuration_line& line = b.configurations[variant];
        if (line.comments.empty() && line.text.empty())
            line.comments = {"# The set-up " + variant + "'s library ran with; a run with another fails the gate."};
        line.text = now->second;
    }
    if (old.contracts.empty() && !b.contracts.empty())
        b.contracts.begin()->second.comments = {
            "# The contract each variant was judged by; a run under another fails the gate."};
    b.figures.clear();
    b.comments.clear();
    for (const auto& [key, value] : old.figures)
        if (!run.count(key.target)) b.figures.emplace(key, value);
    for (const auto& [key, value] : current) b.figures.emplace(key, value);
    for (const auto& [key, lines] : old.comments) {
        if (b.figures.count(key))
            b.comments[key] = lines;
        else
            b.trailing_comments.insert(b.trailing_comments.end(), lines.begin(), lines.end());
    }
    return b;
}

bool gate_result::passed() const {
    if (compared == 0 || !configuration_changes.empty() || !unscored.empty()) return false;
    return std::none_of(changes.begin(), changes.end(), [](const figure_change& c) {
        return c.kind == change_kind::worse || c.kind == change_kind::stale || c.kind == change_kind::missing;
    });
}

namespace {

// One figure against its baseline value under a policy; nullopt when equal
// (for a ULP figure: within `tolerance` of it, relative to the larger).
std::optional<figure_change> judge(const figure_key& key, double before, double after, const gate_policy& policy,
                                   double tolerance) {
    if (before == after) return std::nullopt;
    if (is_ulp_figure(key.figure) && std::abs(after - before) <= tolerance * std::max(std::abs(before), std::abs(after)))
        return std::nullopt;
    figure_change change{key, before, after, change_kind::better, 0};
    // Fewer scored cases is worse (a case left unscored passed nothing); of every other figure, more.
    if (key.figure == scored_figure) {
        if (after > before) return change;
        change.limit = before - policy.count_slack;
        change.kind = after < change.limit ? change_kind::worse : change_kind::within_slack;
        return change;
    }
    if (after < before) return change;
    change.limit = is_ulp_figure(key.figure) ? before * policy.ulp_slack : before + policy.count_slack;
    change.kind = after > change.limit ? change_kind::worse : change_kind::within_slack;
    return change;
}

// Whether a family or target the baseline holds may be absent from a run;
// nullptr: absence is only noted (`rayverify diff` compares what both have).
using absence_rule = std::function<bool(const std::string& target, const std::string& family)>;

template <class PolicyOf>
gate_result compare_tables(const figure_table& before, const figure_table& after, const PolicyOf& policy_of,
                    const absence_rule* may_be_absent, double tolerance) {
    gate_result result;
    std::set<std::string> targets_run, targets_known;
    for (const auto& entry : after) targets_run.insert(entry.first.target);
    for (const auto& entry : before) targets_known.insert(entry.first.target);

    // Which (target, family) groups are comparable, from their case counts.
    std::set<std::pair<std::string, std::string>> skipped;
    for (const auto& [key, value] : after) {
        if (key.figure != "cases") continue;
        const auto old = before.find(key);
        if (old == before.end()) {
            if (!targets_known.count(key.target)) {
                if (key.family == all_families)
                    result.notes.push_back(fmt::format("{}: new, no baseline", key.target));
            } else {
                result.notes.push_back(fmt::format("{} {}: new family, no baseline", key.target, key.family));
            }
            skipped.insert({key.target, key.family});
        } else if (old->second != value) {
            skipped.insert({key.target, key.family});
            if (key.family == all_families)
                result.notes.push_back(fmt::format("{} all: corpus has {} cases, baseline {}; whole-corpus figures "
                                                   "not compared (families are)",
                                                   key.target, value, old->second));
            else
                result.changes.push_back({key, old->second, value, change_kind::stale, 0});
        }
    }
    for (const auto& [key, value] : after) {
        if (key.figure == "cases" || skipped.count({key.target, key.family})) continue;
        const auto old = before.find(key);
        if (old == before.end()) {
            result.changes.push_back({key, std::nullopt, value, change_kind::new_entry, 0});
            continue;
        }
        ++result.compared;
        if (auto change = judge(key, old->second, value, policy_of(key.target), tolerance))
            result.changes.push_back(*change);
    }
    // A baseline figure with no current value: its error statistics have no sample any more.
    std::set<std::pair<std::string, std::string>> missing_families;
    for (const auto& [key, value] : before) {
        if (!targets_run.count(key.target) || after.count(key)) continue;
        if (key.figure == "cases")
            missing_families.insert({key.target, key.family});
        else if (!missing_families.count({key.target, key.family}))
            result.notes.push_back(fmt::format("{}: in the baseline ({}), no value in this run (no agreeing case)",
                                               key.text(), number_text(value)));
    }
    const auto absent = [&](const std::string& target, const std::string& family, const std::string& what) {
        if (may_be_absent == nullptr || (*may_be_absent)(target, family)) {
            result.notes.push_back(fmt::format("{} {}: in the baseline, {}{}", target, family, what,
                                               may_be_absent == nullptr ? "" : " (allowed)"));
            return;
        }
        const auto cases = before.find({target, family, "cases"});
        result.changes.push_back({{target, family, "cases"},
                                  cases == before.end() ? std::nullopt : std::optional<double>(cases->second),
                                  std::nullopt, change_kind::missing, 0});
    };
    for (const auto& [target, family] : missing_families) absent(target, family, "not in this corpus");
    if (may_be_absent != nullptr)
        for (const std::string& t : targets_known)
            if (!targets_run.count(t)) absent(t, std::string(all_families), "not run");
    std::stable_sort(result.changes.begin(), result.changes.end(),
                     [](const figure_change& a, const figure_change& b) { return a.key < b.key; });
    return result;
}

}  // namespace

gate_result compare_to_baseline(const baseline& base, const figure_table& current, double tolerance,
                                const configuration_table& current_configurations,
                                const std::vector<std::string>& allow_missing,
                                const configuration_table& current_contracts) {
    std::set<std::string> allowed(allow_missing.begin(), allow_missing.end());
    for (const auto& [name, unused] : base.allowed_missing) allowed.insert(name);
    const absence_rule may_be_absent = [&](const std::string& target, const std::string& family) {
        return allowed.count(family) > 0 || allowed.count(target) > 0 || allowed.count(variant_of(target)) > 0;
    };
    gate_result result = compare_tables(
        base.figures, current, [&](const std::string& target) { return base.policy_for(target); }, &may_be_absent,
        tolerance);
    std::set<std::string> variants_run, variants_known;
    for (const auto& entry : current) variants_run.insert(variant_of(entry.first.target));
    for (const auto& entry : base.figures) variants_known.insert(variant_of(entry.first.target));
    // What each variant ran under, against what the baseline records of it: a
    // library set-up a run does not report is compared as none; a contract only
    // where the caller knows the variant's.
    const auto compare_setups = [&](setup_aspect aspect, const std::map<std::string, configuration_line>& recorded,
                                    const configuration_table& now) {
        for (const std::string& variant : variants_run) {
            const auto reported = now.find(variant);
            if (reported == now.end() && aspect == setup_aspect::contract) continue;
            const std::string after = reported == now.end() ? std::string() : reported->second;
            if (const auto line = recorded.find(variant); line != recorded.end()) {
                if (line->second.text != after)
                    result.configuration_changes.push_back({variant, line->second.text, after, aspect});
            } else if (!after.empty() && variants_known.count(variant)) {
                result.notes.push_back(fmt::format("{}: the baseline records no {}; this run's: {} "
                                                   "(--update records it)",
                                                   variant, setup_aspect_name(aspect), after));
            }
        }
    };
    compare_setups(setup_aspect::library, base.configurations, current_configurations);
    compare_setups(setup_aspect::contract, base.contracts, current_contracts);
    return result;
}

gate_result compare_figures(const figure_table& before, const figure_table& after, const gate_policy& policy,
                            double tolerance) {
    return compare_tables(before, after, [&](const std::string&) { return policy; }, nullptr, tolerance);
}

void gate_examples::add(const audited_case& c, const std::vector<audit_target>& targets) {
    if (per_figure_ == 0) return;
    const std::string family = family_key(*c.source);
    for (std::size_t t = 0; t < targets.size(); ++t) {
        const verdict_kind verdict = c.outcomes[t].score.verdict;
        if (!is_disagreement(verdict)) continue;
        for (const std::string& f : {std::string(all_families), family}) {
            auto& list = cases_[{targets[t].label(), f, std::string(verdict_name(verdict))}];
            if (list.size() < per_figure_) list.push_back(c.source);
        }
    }
}

std::vector<const corpus_case*> gate_examples::cases_for(const figure_key& key, const audit_totals& totals,
                                                         std::span<const corpus_case> corpus) const {
    if (!is_ulp_figure(key.figure)) {
        const auto it = cases_.find(key);
        return it == cases_.end() ? std::vector<const corpus_case*>{} : it->second;
    }
    for (std::size_t t = 0; t < totals.targets.size(); ++t) {
        if (totals.targets[t].label() != key.target) continue;
        const target_tally* tally = &totals.overall[t];
        if (key.family != all_families) {
            const auto family = totals.by_family.find(key.family);
            if (family == totals.by_family.end()) return {};
            tally = &family->second[t];
        }
        for (const error_figure_definition& f : error_figures) {
            if (!f.gated || !key.figure.starts_with(std::string(f.case_name) + "_")) continue;
            for (const corpus_case& c : corpus)
                if (c.id == tally->errors[f.figure].max_case) return {&c};
        }
    }
    return {};
}

gate_run run_gate(std::span<const corpus_case> cases, const std::vector<audit_target>& targets,
                  const baseline& base, std::size_t examples_per_figure, unsigned threads, double tolerance,
                  const std::vector<std::string>& allow_missing) {
    gate_run run;
    run.examples = gate_examples(examples_per_figure);
    run.totals = run_audit(cases, targets, [&](const audited_case& c) { run.examples.add(c, targets); }, {}, threads);
    run.current = figures_of(run.totals);
    run.configurations = configurations_of(targets);
    run.contracts = contracts_of(targets);
    run.result = compare_to_baseline(base, run.current, tolerance, run.configurations, allow_missing, run.contracts);
    for (std::size_t i = 0; i < run.totals.targets.size(); ++i)
        if (run.totals.overall[i].scored_nothing())
            run.result.unscored.push_back(run.totals.targets[i].label());
    return run;
}

}  // namespace rayverify
