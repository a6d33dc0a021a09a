#include "report/audit_summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>

#include "compare/error_figures.h"

namespace rayverify {
namespace {

// One variant's tallies, float and double (absent when it did not run there).
struct member {
    std::string name;
    std::array<const target_tally*, 2> tally{};

    // Wrong answers over scored cases, both precisions together.
    double wrong_share() const {
        std::size_t wrong = 0, total = 0;
        for (const target_tally* t : tally)
            if (t) wrong += t->disagreements(), total += t->scored();
        return total ? static_cast<double>(wrong) / static_cast<double>(total) : 0.0;
    }
};

std::string share_text(const target_tally* t) {
    if (!t) return "-";
    const std::size_t n = t->scored();
    if (n == 0) return "no cases";
    const double share = 100.0 * static_cast<double>(t->disagreements()) / static_cast<double>(n);
    return t->disagreements() == 0 ? "0" : fmt::format("{:.3g}%", share);
}

std::string ulp_text(const target_tally* t) {
    if (!t || t->errors[error_figure::near_root_ulp].count == 0) return "-";
    return format_figure(t->errors[error_figure::near_root_ulp].max);
}

// The disagreement a member gives most often (over both precisions), with its count.
std::string commonest_text(const member& m) {
    std::size_t best = 0;
    int kind = -1;
    for (int k = 0; k < verdict_kind_count; ++k) {
        if (!is_disagreement(static_cast<verdict_kind>(k))) continue;
        std::size_t n = 0;
        for (const target_tally* t : m.tally)
            if (t) n += t->verdicts[k];
        if (n > best) best = n, kind = k;
    }
    return kind < 0 ? "-" : fmt::format("{} {}", verdict_name(static_cast<verdict_kind>(kind)), best);
}

}  // namespace

std::string variant_family(const std::string& name, const std::vector<std::string>& names) {
    std::string family = name;
    for (const std::string& other : names)
        if (other.size() < family.size() && name.size() > other.size() && name.starts_with(other) &&
            name[other.size()] == '_')
            family = other;
    return family;
}

std::string render_family_summary(const audit_totals& totals) {
    // Members in report order, each once.
    std::vector<member> members;
    for (std::size_t i = 0; i < totals.targets.size(); ++i) {
        const std::string& name = totals.targets[i].subject.name;
        auto it = std::find_if(members.begin(), members.end(), [&](const member& m) { return m.name == name; });
        if (it == members.end()) it = members.insert(members.end(), member{name, {}});
        it->tally[totals.targets[i].prec == precision::binary32 ? 0 : 1] = &totals.overall[i];
    }
    std::vector<std::string> names;
    for (const member& m : members) names.push_back(m.name);
    // Families in the order of their first member.
    std::vector<std::pair<std::string, std::vector<const member*>>> families;
    for (const member& m : members) {
        const std::string family = variant_family(m.name, names);
        auto it = std::find_if(families.begin(), families.end(), [&](const auto& f) { return f.first == family; });
        if (it == families.end()) it = families.insert(families.end(), {family, {}});
        it->second.push_back(&m);
    }

    std::size_t family_width = 6, name_width = 19;
    for (const auto& [family, list] : families) {
        family_width = std::max(family_width, family.size());
        for (const member* m : list) name_width = std::max(name_width, m->name.size());
    }
    const auto by_share = [](const member* a, const member* b) { return a->wrong_share() < b->wrong_share(); };
    const auto row = [&](std::string_view family, std::string_view count, std::string_view best,
                         std::string_view wrong_float, std::string_view wrong_double, std::string_view commonest,
                         std::string_view ulp_float, std::string_view ulp_double, std::string_view worst) {
        std::string line = fmt::format("{:<{}} {:>8}  {:<{}} {:>11} {:>7}  {:<20} {:>13} {:>9}  {}", family,
                                       family_width, count, best, name_width, wrong_float, wrong_double, commonest,
                                       ulp_float, ulp_double, worst);
        line.erase(line.find_last_not_of(' ') + 1);
        return line + '\n';
    };
    std::string out = row("family", "variants", "best (fewest wrong)", "wrong float", "double", "commonest wrong",
                          "max ulp float", "double", "worst");
    for (const auto& [family, list] : families) {
        const member& best = **std::min_element(list.begin(), list.end(), by_share);
        const member& worst = **std::max_element(list.begin(), list.end(), by_share);
        const std::string worst_text =
            list.size() == 1 ? std::string() : fmt::format("{} {:.3g}%", worst.name, 100.0 * worst.wrong_share());
        out += row(family, std::to_string(list.size()), best.name, share_text(best.tally[0]),
                   share_text(best.tally[1]), commonest_text(best), ulp_text(best.tally[0]), ulp_text(best.tally[1]),
                   worst_text);
    }
    out += fmt::format("{} cases, {} variant{} in {} famil{}. wrong: share of the scored cases whose answer "
                       "disagrees with the exact one;\nmax ulp: largest nearest-root error where it agrees (-: no "
                       "root returned); worst: the family's most-wrong member. Full table: without --summary.\n",
                       totals.cases, members.size(), members.size() == 1 ? "" : "s", families.size(),
                       families.size() == 1 ? "y" : "ies");
    if (!totals.invalid_list.empty())
        out += fmt::format("invalid cases: {} (not scored; named without --summary and in report.json)\n",
                           totals.invalid_list.size());
    return out;
}

}  // namespace rayverify
