#include <fmt/format.h>

#include "cli/commands.h"
#include "intersectors/registry.h"
#include "report/audit_report.h"

namespace rayverify::cli {

command add_variants_command(CLI::App& app) {
    auto* sub = app.add_subcommand("variants", "List the built-in intersectors with their formulas and contracts");
    auto as_json = std::make_shared<bool>(false);
    sub->add_flag("--json", *as_json, "Print the registry as JSON");
    return {sub, [as_json] {
                if (*as_json) {
                    nlohmann::ordered_json all = nlohmann::ordered_json::array();
                    for (const variant& v : builtin_variants())
                        all.push_back({{"name", v.name},
                                       {"citation", v.citation},
                                       {"formula", v.formula},
                                       {"contract", contract_json(v.promises)},
                                       {"precisions", {"float", "double"}}});
                    fmt::print("{}\n", all.dump(2));
                    return exit_ok;
                }
                for (const variant& v : builtin_variants()) {
                    const contract& c = v.promises;
                    fmt::print("{}\n  source:    {}\n  formula:   {}\n", v.name, v.citation, v.formula);
                    fmt::print("  answers:   {}\n", describe_contract(c));
                    fmt::print("  contract:  {}\n", format_contract(c));
                    if (c.reports_tangent) fmt::print("  tangent:   {}\n", c.tangent_rule);
                    fmt::print("  precision: float, double\n\n");
                }
                return exit_ok;
            }};
}

}  // namespace rayverify::cli
