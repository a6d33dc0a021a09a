#include "report/builds_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "corpus/corpus_io.h"

namespace rayverify {

using json = nlohmann::ordered_json;

namespace {

std::string answer_text(const variant_output& o) {
    if (o.roots.count == 0) return "no hit";
    if (o.roots.count == 1) return fmt::format("t = {}", o.roots.t0);
    if (o.roots.count == 2) return fmt::format("t = {}, {}", o.roots.t0, o.roots.t1);
    return fmt::format("a count of {}", o.roots.count);
}

// The shell's single quotes around `text` (a corpus line has no quote in it,
// but a quote is escaped all the same).
std::string quoted(const std::string& text) {
    std::string out = "'";
    for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string cases_text(std::size_t n) { return fmt::format("{} case{}", n, n == 1 ? "" : "s"); }

std::string flip_text(const json& f) {
    return fmt::format("{} -> {}", f["reference"].get<std::string>(), f["build"].get<std::string>());
}

std::string words(const json& list) {
    std::vector<std::string> out;
    for (const json& w : list) out.push_back(w.get<std::string>());
    return out.empty() ? std::string("no flag (the compiler alone)") : fmt::format("{}", fmt::join(out, " "));
}

}  // namespace

std::string_view build_outcome_name(build_row::outcome o) {
    switch (o) {
        case build_row::outcome::ran: return "ran";
        case build_row::outcome::refused_by_source: return "refused_by_source";
        case build_row::outcome::did_not_compile: return "did_not_compile";
        case build_row::outcome::did_not_load: return "did_not_load";
        case build_row::outcome::failed_in_audit: return "failed_in_audit";
    }
    return "ran";
}

json builds_json(std::span<const build_row> rows, std::span<const audit_target> targets,
                 std::span<const build_difference> differences, std::size_t cases, std::size_t examples) {
    json out;
    for (const build_row& r : rows)
        if (r.reference) out["reference"] = r.name;
    out["cases"] = cases;
    json list = json::array();
    for (const build_row& r : rows) {
        json row;
        row["name"] = r.name;
        row["compiler"] = r.compiler;
        row["compiler_version"] = r.compiler_version;
        row["flags"] = r.flags;
        row["reference"] = r.reference;
        row["status"] = build_outcome_name(r.status);
        if (!r.failure.empty()) row["failure"] = r.failure;
        row["cached"] = r.cached;
        row["commands"] = r.commands;
        if (!r.plugin.empty()) row["plugin"] = r.plugin;
        if (!r.fp_environment.empty()) row["fp_environment"] = r.fp_environment;
        json precisions = json::array();
        for (const build_difference& d : differences) {
            if (targets[d.target].subject.name != r.name) continue;
            const std::string precision(precision_name(targets[d.target].prec));
            json p;
            p["precision"] = precision;
            p["cases"] = d.cases;
            p["answers_changed"] = d.answers_changed;
            p["verdicts_flipped"] = d.verdicts_flipped();
            json flips = json::array();
            for (const auto& [kinds, count] : flips_worst_first({d.flips.begin(), d.flips.end()}))
                flips.push_back({{"reference", verdict_name(kinds.first)}, {"build", verdict_name(kinds.second)},
                                 {"cases", count}});
            p["flips"] = flips;
            p["better"] = d.better;
            p["worse"] = d.worse;
            json worst = json::array();
            for (const build_flip& f : d.worst(examples))
                worst.push_back({{"id", f.source.id},
                                 {"index", f.index},
                                 {"case", format_case_line(f.source)},
                                 {"reference_verdict", verdict_name(f.reference_verdict)},
                                 {"build_verdict", verdict_name(f.build_verdict)},
                                 {"reference_answer", answer_text(f.reference_answer)},
                                 {"build_answer", answer_text(f.build_answer)},
                                 {"detail", f.detail},
                                 {"explain", fmt::format("rayverify explain --plugin {} --precision {} {}", r.plugin,
                                                         precision, quoted(format_case_line(f.source)))}});
            p["worst"] = worst;
            precisions.push_back(p);
        }
        row["precisions"] = precisions;
        if (r.bisect) {
            const build_bisect_result& b = *r.bisect;
            json bisect;
            bisect["components"] = b.components;
            bisect["searched"] = b.searched;
            if (!b.failure.empty()) {
                bisect["failure"] = b.failure;
            } else {
                bisect["smallest"] = b.smallest;
                bisect["cases"] = b.cases;
                bisect["builds_tried"] = b.builds_tried;
                json flips = json::array();
                for (const auto& f : b.flips)
                    flips.push_back({{"reference", verdict_name(f.reference)},
                                     {"build", verdict_name(f.build)},
                                     {"cases", f.cases},
                                     {"smallest", f.smallest}});
                bisect["flips"] = flips;
            }
            row["bisect"] = bisect;
        }
        list.push_back(row);
    }
    out["rows"] = list;
    return out;
}

std::string render_builds_text(const json& builds) {
    std::string out = fmt::format("builds: each against the reference build {} on {} cases\n",
                                  builds.value("reference", std::string("(none)")), builds["cases"].get<std::size_t>());
    std::size_t width = 5;
    for (const json& r : builds["rows"]) width = std::max(width, r["name"].get<std::string>().size());
    out += fmt::format("{:<{}}  {:<9} {:>7} {:>8} {:>8} {:>7} {:>7}\n", "build", width, "precision", "scored",
                       "changed", "flipped", "better", "worse");
    for (const json& r : builds["rows"]) {
        const std::string name = r["name"].get<std::string>();
        const std::string status = r["status"].get<std::string>();
        if (status != "ran") {
            const std::string failure = r.value("failure", std::string());
            const std::string said = status == "refused_by_source" ? "refused by the source (its #error)"
                                     : status == "did_not_compile" ? "did not compile"
                                     : status == "did_not_load" ? "did not load"
                                                                : "failed while audited (no figures)";
            out += fmt::format("{:<{}}  {}: {}\n", name, width, said, failure);
            continue;
        }
        if (r["reference"].get<bool>()) {
            out += fmt::format("{:<{}}  the reference ({} {})\n", name, width, r["compiler"].get<std::string>(),
                               r["flags"].get<std::string>());
            continue;
        }
        std::size_t changed = 0, flipped = 0;
        for (const json& p : r["precisions"]) {
            changed += p["answers_changed"].get<std::size_t>();
            flipped += p["verdicts_flipped"].get<std::size_t>();
        }
        if (changed == 0 && flipped == 0) {
            out += fmt::format("{:<{}}  same answers as the reference, bit for bit, in every precision\n", name, width);
            continue;
        }
        for (const json& p : r["precisions"]) {
            out += fmt::format("{:<{}}  {:<9} {:>7} {:>8} {:>8} {:>7} {:>7}\n", name, width,
                               p["precision"].get<std::string>(), p["cases"].get<std::size_t>(),
                               p["answers_changed"].get<std::size_t>(), p["verdicts_flipped"].get<std::size_t>(),
                               p["better"].get<std::size_t>(), p["worse"].get<std::size_t>());
            if (!p["flips"].empty()) {
                std::vector<std::string> flips;
                for (const json& f : p["flips"])
                    flips.push_back(fmt::format("{} {}", flip_text(f), f["cases"].get<std::size_t>()));
                out += fmt::format("    flips: {}\n", fmt::join(flips, ", "));
            }
            for (const json& w : p["worst"]) {
                out += fmt::format("    {} ({} -> {}): the reference {}, this build {}\n", w["id"].get<std::string>(),
                                   w["reference_verdict"].get<std::string>(), w["build_verdict"].get<std::string>(),
                                   w["reference_answer"].get<std::string>(), w["build_answer"].get<std::string>());
                if (!w["detail"].get<std::string>().empty())
                    out += fmt::format("      {}\n", w["detail"].get<std::string>());
                out += fmt::format("      {}\n", w["explain"].get<std::string>());
            }
        }
        if (r.contains("bisect")) {
            const json& b = r["bisect"];
            if (b.contains("failure")) {
                out += fmt::format("    bisect: {}\n", b["failure"].get<std::string>());
                continue;
            }
            out += fmt::format("    bisect over {}: {} reproduce{} its {} changed answers ({} builds tried): what to "
                               "keep out of this file's build\n",
                               b["searched"].get<std::string>(), words(b["smallest"]),
                               b["smallest"].size() <= 1 ? "s" : "", b["cases"].get<std::size_t>(),
                               b["builds_tried"].get<std::size_t>());
            for (const json& f : b["flips"])
                out += fmt::format("      {} ({}): {}\n", flip_text(f), cases_text(f["cases"].get<std::size_t>()),
                                   words(f["smallest"]));
        }
    }
    return out;
}

std::string render_builds_markdown(const json& builds) {
    std::string out = fmt::format(
        "Each build's answers against the reference build `{}`, case by case, bit for bit ({} cases); verdict rows "
        "per build are in the table above.\n\n"
        "| build | compiler | flags | precision | scored | answers changed | verdicts flipped | better | worse |\n"
        "|---|---|---|---|---:|---:|---:|---:|---:|\n",
        builds.value("reference", std::string("(none)")), builds["cases"].get<std::size_t>());
    std::string details;
    for (const json& r : builds["rows"]) {
        const std::string name = r["name"].get<std::string>(), status = r["status"].get<std::string>();
        const std::string head = fmt::format("| `{}` | {} | `{}` ", name, r["compiler"].get<std::string>(),
                                             r["flags"].get<std::string>());
        if (status != "ran") {
            out += head + fmt::format("| {}: {} |||||\n", status, r.value("failure", std::string()));
            continue;
        }
        if (r["reference"].get<bool>()) {
            out += head + "| the reference |||||\n";
            continue;
        }
        for (const json& p : r["precisions"])
            out += head + fmt::format("| {} | {} | {} | {} | {} | {} |\n", p["precision"].get<std::string>(),
                                      p["cases"].get<std::size_t>(), p["answers_changed"].get<std::size_t>(),
                                      p["verdicts_flipped"].get<std::size_t>(), p["better"].get<std::size_t>(),
                                      p["worse"].get<std::size_t>());
        std::string mine;
        for (const json& p : r["precisions"])
            for (const json& w : p["worst"])
                mine += fmt::format("- `{}` ({}, {} -> {}): the reference {}, this build {}. {}\n  `{}`\n",
                                    w["id"].get<std::string>(), p["precision"].get<std::string>(),
                                    w["reference_verdict"].get<std::string>(), w["build_verdict"].get<std::string>(),
                                    w["reference_answer"].get<std::string>(), w["build_answer"].get<std::string>(),
                                    w["detail"].get<std::string>(), w["explain"].get<std::string>());
        if (r.contains("bisect")) {
            const json& b = r["bisect"];
            if (b.contains("failure"))
                mine += fmt::format("- bisect: {}\n", b["failure"].get<std::string>());
            else {
                mine += fmt::format("- **what to keep out of this file's build**: `{}` reproduce{} its {} changed "
                                    "answers (bisect over {}, {} builds tried)\n",
                                    words(b["smallest"]), b["smallest"].size() <= 1 ? "s" : "",
                                    b["cases"].get<std::size_t>(), b["searched"].get<std::string>(),
                                    b["builds_tried"].get<std::size_t>());
                for (const json& f : b["flips"])
                    mine += fmt::format("  - {} ({}): `{}`\n", flip_text(f), cases_text(f["cases"].get<std::size_t>()),
                                        words(f["smallest"]));
            }
        }
        if (!mine.empty()) details += fmt::format("\n**{}**\n\n{}", name, mine);
    }
    out += details;
    std::string commands;
    for (const json& r : builds["rows"]) {
        commands += fmt::format("\n`{}`{}:\n\n```\n", r["name"].get<std::string>(),
                                r["cached"].get<bool>() ? " (from the cache)" : "");
        for (const json& c : r["commands"]) commands += c.get<std::string>() + "\n";
        commands += "```\n";
    }
    out += "\n<details><summary>Every build's commands</summary>\n" + commands + "\n</details>\n";
    return out;
}

}  // namespace rayverify
