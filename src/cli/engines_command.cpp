// `rayverify engines`: the engines' libraries rayverify audits as shipped
// (cli/shipped_libraries.h), one line each: name, version, where it comes
// from, precision, contract, and whether it can be audited here.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/shipped_libraries.h"

namespace rayverify::cli {
namespace {

std::string precisions_text(const std::vector<precision>& precisions) {
    std::string out;
    for (precision p : precisions) out += (out.empty() ? "" : ",") + std::string(precision_name(p));
    return out.empty() ? "-" : out;
}

int list_engines() {
    const std::vector<shipped_library>& all = shipped_libraries();
    std::size_t widths[4] = {4, 7, 6, 9};
    for (const shipped_library& l : all) {
        widths[0] = std::max(widths[0], l.name.size());
        widths[1] = std::max(widths[1], std::max<std::size_t>(1, l.identity.version.size()));
        widths[2] = std::max(widths[2], l.identity.source.size());
        widths[3] = std::max(widths[3], precisions_text(l.precisions).size());
    }
    fmt::print("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}\n", "name", widths[0], "version", widths[1], "source", widths[2],
               "precision", widths[3], "contract  status");
    std::size_t available = 0;
    for (const shipped_library& l : all) {
        available += l.available() ? 1 : 0;
        fmt::print("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}  {}\n", l.name, widths[0],
                   l.identity.version.empty() ? "-" : l.identity.version, widths[1], l.identity.source, widths[2],
                   precisions_text(l.precisions), widths[3], l.contract.empty() ? "-" : l.contract,
                   l.available() ? "available" : "not available: " + l.why_not);
    }
    fmt::print("{} of {} engine libraries available; audit one with --engine NAME (docs/engines.md)\n", available,
               all.size());
    return exit_ok;
}

}  // namespace

command add_engines_command(CLI::App& app) {
    auto* sub = app.add_subcommand(
        "engines",
        "List the engines' libraries rayverify audits as their packages install them (Debian and npm packages), "
        "each with its version, source, precision, contract and whether it is available here; audit one with "
        "--engine NAME");
    return {sub, [] { return list_engines(); }};
}

}  // namespace rayverify::cli
