#include <fmt/format.h>

#include <fstream>

#include "cli/commands.h"
#include "compare/gate.h"
#include "core/input_error.h"
#include "report/gate_report.h"

namespace rayverify::cli {
namespace {

figure_table read_report(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw input_error(path, 0, "report", "cannot open for reading");
    nlohmann::json report;
    try {
        report = nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error& e) {
        throw input_error(path, 0, "report", fmt::format("not JSON: {}", e.what()));
    }
    return figures_from_report_json(report, path);
}

}  // namespace

command add_diff_command(CLI::App& app) {
    auto paths = std::make_shared<std::vector<std::string>>();
    auto tolerance = std::make_shared<double>(default_figure_tolerance);
    auto* sub = app.add_subcommand("diff", "Compare two report.json files (rayverify audit --report) figure by "
                                           "figure: what changed from A to B. Exit 1 when some figure of B is worse.");
    sub->add_option("reports", *paths, "A.json B.json")->required()->expected(2);
    add_tolerance_option(sub, *tolerance);
    return {sub, [paths, tolerance] {
                const figure_table a = read_report((*paths)[0]), b = read_report((*paths)[1]);
                const gate_result result = compare_figures(a, b, gate_policy{}, *tolerance);
                fmt::print("{}", terminal::coloured_verdicts(render_figure_diff(result)));
                for (const figure_change& c : result.changes)
                    if (c.kind == change_kind::worse) return exit_findings;
                return exit_ok;
            }};
}

}  // namespace rayverify::cli
