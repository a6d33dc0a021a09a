#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/commands.h"
#include "compare/gate.h"
#include "core/input_error.h"
#include "corpus/json_input.h"
#include "report/gate_report.h"

namespace rayverify::cli {
namespace {

figure_table read_report(const std::string& path) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error))
        throw input_error(path, 0, "report", "is a directory, expected a report.json file");
    if (std::filesystem::exists(path, error) && !std::filesystem::is_regular_file(path, error))
        throw input_error(path, 0, "report", "is not a regular file (a FIFO, a device or a socket), expected a report.json file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error(path, 0, "report", "cannot open for reading");
    std::stringstream text;
    text << in.rdbuf();
    return figures_from_report_json(parse_json_input(text.str(), path), path);
}

}  // namespace

command add_diff_command(CLI::App& app) {
    auto paths = std::make_shared<std::vector<std::string>>();
    auto tolerance = std::make_shared<double>(default_figure_tolerance);
    auto* sub = app.add_subcommand("diff", "Compare two report.json files (rayverify audit --report) figure by "
                                           "figure: what changed from A to B. Exit 1 when `gate` would fail with A as "
                                           "the baseline: some figure of B is worse, a family's case count changed, "
                                           "or no figure could be compared at all.");
    sub->add_option("reports", *paths, "A.json B.json")->required()->expected(2);
    add_tolerance_option(sub, *tolerance);
    return {sub, [paths, tolerance] {
                const figure_table a = read_report((*paths)[0]), b = read_report((*paths)[1]);
                const gate_result result = compare_figures(a, b, gate_policy{}, *tolerance);
                fmt::print("{}", terminal::coloured_verdicts(render_figure_diff(result)));
                if (result.compared == 0)
                    fmt::print("diff: no figure of B has a counterpart in A with the same case count: nothing "
                               "was compared, which fails as `gate` does\n");
                return result.passed() ? exit_ok : exit_findings;
            }};
}

}  // namespace rayverify::cli
