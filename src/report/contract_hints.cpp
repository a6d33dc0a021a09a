#include "report/contract_hints.h"

#include <fmt/format.h>

#include "plugin/plugin_loader.h"

namespace rayverify {

nlohmann::ordered_json contract_hints_json(const std::vector<audit_target>& targets,
                                           const std::vector<std::optional<contract_hint>>& hints) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (std::size_t t = 0; t < targets.size() && t < hints.size(); ++t) {
        if (!hints[t]) continue;
        const contract_hint& h = *hints[t];
        const std::optional<std::string> v1 = version1_query_name(h.candidate.promises);
        out.push_back({{"target", targets[t].label()},
                       {"declared", format_contract(targets[t].subject.promises)},
                       {"suggested", format_contract(h.candidate.promises)},
                       {"plugin_query", v1 ? nlohmann::ordered_json(*v1) : nlohmann::ordered_json(nullptr)},
                       {"pattern", h.candidate.pattern},
                       {"scored", h.scored},
                       {"disagreements", h.wrong},
                       {"fixed", h.fixed},
                       {"broken", h.broken}});
    }
    return out;
}

std::string render_contract_hints(const nlohmann::ordered_json& hints) {
    std::string out;
    for (const auto& h : hints) {
        const std::string target = h.at("target").get<std::string>();
        const std::string said = h.at("plugin_query").is_string()
                                     ? fmt::format(" ({} in rayverify_plugin.h)", h.at("plugin_query").get<std::string>())
                                     : std::string();
        out += fmt::format("hint: {} answers as another contract would: {}.\n", target,
                           h.at("pattern").get<std::string>());
        out += fmt::format("  declared:  {}\n", h.at("declared").get<std::string>());
        out += fmt::format("  fits:      {}{}\n", h.at("suggested").get<std::string>(), said);
        out += fmt::format("  judged again under it, {} of its {} disagreements would agree and {} agreeing "
                           "case{} would not ({} cases scored). Templates: docs/plugins.md#templates\n",
                           h.at("fixed").get<std::size_t>(), h.at("disagreements").get<std::size_t>(),
                           h.at("broken").get<std::size_t>(), h.at("broken").get<std::size_t>() == 1 ? "" : "s",
                           h.at("scored").get<std::size_t>());
    }
    return out;
}

}  // namespace rayverify
