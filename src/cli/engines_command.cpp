// `rayverify engines`: the engines' libraries rayverify audits as shipped
// (cli/shipped_libraries.h), one line each: name, version, where it comes
// from, precision, contract, and whether it can be audited here (with the
// set-up it runs, such as the kernel Embree picked); then which targets'
// answers depend on the CPU, and why.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string>
#include <utility>
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

std::string status_text(const shipped_library& l) {
    if (!l.available()) return (l.runs_elsewhere_only ? "not runnable here: " : "not available: ") + l.why_not;
    return l.identity.configuration.empty() ? "available" : "available (" + l.identity.configuration + ")";
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
    std::vector<std::string> with_kernels;  // the targets whose kernels others pin, in list order
    for (const shipped_library& l : all) {
        available += l.available() ? 1 : 0;
        if (!l.kernel_of.empty() && std::find(with_kernels.begin(), with_kernels.end(), l.kernel_of) == with_kernels.end())
            with_kernels.push_back(l.kernel_of);
        fmt::print("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}  {}\n", l.name, widths[0],
                   l.identity.version.empty() ? "-" : l.identity.version, widths[1], l.identity.source, widths[2],
                   precisions_text(l.precisions), widths[3], l.contract.empty() ? "-" : l.contract, status_text(l));
    }
    std::string kernels;
    for (const std::string& of : with_kernels)
        kernels += fmt::format(", every pinned kernel of {0} this CPU runs with --engine {0}{1}", of, every_kernel_suffix);
    fmt::print("{} of {} engine targets available; audit one with --engine NAME{} (docs/engines.md)\n", available,
               all.size(), kernels);
    // Which targets' answers depend on the CPU, grouped by why.
    std::vector<std::pair<std::string, std::vector<std::string>>> reasons;
    for (const shipped_library& l : all) {
        if (l.depends_on_cpu.empty()) continue;
        auto it = std::find_if(reasons.begin(), reasons.end(), [&](const auto& r) { return r.first == l.depends_on_cpu; });
        if (it == reasons.end()) it = reasons.insert(reasons.end(), {l.depends_on_cpu, {}});
        it->second.push_back(l.name);
    }
    for (const auto& [why, names] : reasons)
        fmt::print("answers depend on the CPU: {}: {}\n", fmt::join(names, ", "), why);
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
