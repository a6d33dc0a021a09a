#include <fmt/format.h>

#include "cli/commands.h"
#include "intersectors/registry.h"
#include "report/audit_report.h"
#include "report/schema.h"

namespace rayverify::cli {

command add_variants_command(CLI::App& app) {
    auto* sub = app.add_subcommand("variants", "List the built-in intersectors with their formulas and contracts");
    auto as_json = std::make_shared<bool>(false);
    sub->add_flag("--json", *as_json, "Print the registry as JSON");
    return {sub, [as_json] {
                if (*as_json) {
                    nlohmann::ordered_json all = nlohmann::ordered_json::array();
                    for (const variant& v : builtin_variants()) {
                        const contract& c = v.promises;
                        all.push_back({{"name", v.name},
                                       {"citation", v.citation},
                                       {"formula", v.formula},
                                       {"query", query_kind_name(c.query)},
                                       {"assumes_unit_direction", c.assumes_unit_direction},
                                       {"reports_tangent", c.reports_tangent},
                                       {"tangent_rule", std::string(c.tangent_rule)},
                                       {"clamps_to_zero", c.clamps_to_zero},
                                       {"precisions", {"float", "double"}}});
                    }
                    const nlohmann::ordered_json document = {{"schema_version", schema_version::variants},
                                                             {"variants", all}};
                    fmt::print("{}\n", document.dump(2));
                    return exit_ok;
                }
                for (const variant& v : builtin_variants()) {
                    const contract& c = v.promises;
                    fmt::print("{}\n  source:   {}\n  formula:  {}\n", v.name, v.citation, v.formula);
                    fmt::print("  returns:  {}\n",
                               c.query == query_kind::line_roots ? "both roots of the line, ordered, negative roots included"
                               : c.query == query_kind::any_hit_in_interval
                                   ? "whether some root lies in the ray's interval (tmin, tmax), no root"
                               : c.query == query_kind::nearest_in_interval
                                   ? "the nearest root in the ray's interval (tmin, tmax)"
                               : (c.clamps_to_zero ? "nearest hit on the ray t >= 0, clamped to 0 when the origin is inside"
                                                   : "nearest hit on the ray t >= 0"));
                    fmt::print("  assumes:  {}\n", c.assumes_unit_direction ? "unit direction (|d|^2 = 1 within 8 eps)"
                                                                           : "any nonzero direction");
                    fmt::print("  tangent:  {}\n  precision: float, double\n\n",
                               c.reports_tangent ? std::string(c.tangent_rule) : std::string("not reported separately"));
                }
                return exit_ok;
            }};
}

}  // namespace rayverify::cli
