#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string>
#include <vector>

#include "cli/commands.h"
#include "intersectors/registry.h"
#include "plugin/plugin_loader.h"
#include "report/audit_report.h"
#include "report/json_line.h"
#include "report/schema.h"

namespace rayverify::cli {

command add_variants_command(CLI::App& app) {
    auto* sub = app.add_subcommand("variants", "List the built-in intersectors with their formulas and contracts");
    auto as_json = std::make_shared<bool>(false);
    auto plugins = std::make_shared<std::vector<std::string>>();
    sub->add_flag("--json", *as_json, "Print the registry as JSON");
    sub->add_option("--plugin", *plugins,
                    "Print this plugin's description and contract as rayverify reads them instead of the built-ins "
                    "(repeatable)");
    return {sub, [as_json, plugins] {
                std::vector<variant> listed;
                for (const std::string& path : *plugins) listed.push_back(load_plugin(path));
                if (plugins->empty()) listed.assign(builtin_variants().begin(), builtin_variants().end());
                const auto precisions = [](const variant& v) {
                    std::vector<std::string> out;
                    for (precision p : {precision::binary32, precision::binary64})
                        if (v.runs_in(p)) out.emplace_back(precision_name(p));
                    return out;
                };
                if (*as_json) {
                    nlohmann::ordered_json all = nlohmann::ordered_json::array();
                    for (const variant& v : listed) {
                        all.push_back({{"name", v.name},
                                       {"citation", v.citation},
                                       {"formula", v.formula},
                                       {"contract", to_json_mapped(v.promises)},
                                       {"precisions", precisions(v)}});
                        if (!v.build.empty()) all.back()["build"] = v.build;
                    }
                    const nlohmann::ordered_json document = {{"schema_version", schema_version::variants},
                                                             {"variants", all}};
                    fmt::print("{}\n", json_text(document, 2));
                    return exit_ok;
                }
                for (const variant& v : listed) {
                    const contract& c = v.promises;
                    fmt::print("{}\n  source:    {}\n  formula:   {}\n", v.name, v.citation, v.formula);
                    fmt::print("  answers:   {}\n", describe_contract(c));
                    fmt::print("  contract:  {}\n", format_contract(c));
                    if (c.reports_tangent) fmt::print("  tangent:   {}\n", c.tangent_rule);
                    fmt::print("  precision: {}\n", fmt::join(precisions(v), ", "));
                    if (!v.build.empty()) fmt::print("  build:     {}\n", v.build);
                    if (!plugins->empty())
                        if (const auto kind = version1_query_name(c)) fmt::print("  kind:      {}\n", *kind);
                    fmt::print("\n");
                }
                return exit_ok;
            }};
}

}  // namespace rayverify::cli
