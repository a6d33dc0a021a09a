#include "report/hunt_file.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "compare/error_figures.h"
#include "core/input_error.h"
#include "core/text_lines.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "corpus/json_input.h"
#include "report/audit_report.h"

namespace rayverify {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

std::string hunt_error_text(hunt_objective objective, double error) {
    switch (objective) {
        case hunt_objective::scale_radius: return "|t − t*|·|d| = " + format_figure(error) + " r";
        case hunt_objective::scale_distance: return "|t − t*|·|d| = " + format_figure(error) + " |o − c|";
        case hunt_objective::ulp:
        case hunt_objective::misclass: break;
    }
    return format_figure(error) + " ulp";
}

namespace {

constexpr std::string_view hunt_prefix = "# rayverify-hunt ";
constexpr std::string_view find_prefix = "# rayverify-find ";
static_assert(hunt_prefix.size() == find_prefix.size(), "a JSON line's text starts at the same column");

// "agree, 3.2 ulp" under an error objective; the verdict otherwise.
std::string outcome(const hunt_record& hunt, verdict_kind verdict, double error) {
    return maximises_error(hunt.objective) ? fmt::format("agree, {}", hunt_error_text(hunt.objective, error))
                                           : std::string(verdict_name(verdict));
}

std::string hunt_summary(const hunt_record& h) {
    const std::string start_cases = h.start_corpus ? fmt::format("start cases from {}", *h.start_corpus)
                                                   : fmt::format("start family {} (seed {})", h.family, h.seed);
    std::string text = fmt::format("# rayverify hunt: {}, objective {}{}, strategy {}, {}\n", h.target,
                                   hunt_objective_name(h.objective), h.rounding_only ? " (rounding causes only)" : "",
                                   hunt_strategy_name(h.strategy), start_cases);
    text += fmt::format("# command: {}\n", h.command);
    std::uint64_t evaluations = 0, starts = 0, shrinking = 0;
    double seconds = 0;
    for (const hunt_run& r : h.runs) {
        evaluations += r.evaluations;
        starts += r.starts;
        shrinking += r.shrink_evaluations;
        seconds += r.seconds;
    }
    if (h.runs.size() == 1 && h.shards > 1)
        text += fmt::format("# shard {} of the hunt, search seed {}\n", h.runs[0].shard.text(), h.runs[0].search_seed);
    if (h.runs.size() > 1)
        text += fmt::format("# merged from {} shards, each an independent hunt with its own start cases and search "
                            "seed (listed in the rayverify-hunt line); totals over all of them:\n",
                            h.runs.size());
    text += fmt::format("# searched {} evaluations from {} start cases in {:.2f} s; {} shrinking evaluations\n",
                        evaluations, starts, seconds, shrinking);
    for (const hunt_run& r : h.runs)
        if (const auto& d = r.first_disagreement)
            text += fmt::format("# {}{} of {} evaluations disagreed with the exact answer; the first ({}) at evaluation "
                                "{}:\n#   {}\n",
                                h.runs.size() > 1 ? "shard " + r.shard.text() + ": " : "", r.disagreements,
                                r.evaluations, verdict_name(d->verdict), d->evaluation, d->case_line);
    if (maximises_error(h.objective))
        text += "# the error below is the largest FOUND BY SEARCH: a lower bound on the variant's maximum over all "
                "inputs, not the maximum\n";
    return text;
}

std::string find_summary(const hunt_record& h, const hunt_file_find& f, std::size_t n) {
    const hunt_find_provenance& p = f.provenance;
    std::string what = outcome(h, p.verdict, p.error);
    if (maximises_error(h.objective)) what += " (lower bound)";
    std::string from = fmt::format("searching from {}", p.start);
    if (h.shards > 1) from += fmt::format(" in shard {} (search seed {})", p.shard.text(), p.search_seed);
    std::string text =
        fmt::format("# find {}: {} at evaluation {} ({:.3f} s), {}\n", n, what, p.evaluation, p.seconds, from);
    if (!p.detail.empty()) text += fmt::format("#   {}\n", p.detail);
    if (p.inputs_changed && p.steps_from_start)
        text += fmt::format("#   shrunk toward {}: {} of the ten inputs differ from it, by {} steps in all; still {}\n",
                            p.start, *p.inputs_changed, *p.steps_from_start,
                            outcome(h, p.shrunk_verdict, p.shrunk_error));
    else
        text += fmt::format("#   shrunk from {} to {} significant bits, still {}\n", p.found_bits, p.shrunk_bits,
                            outcome(h, p.shrunk_verdict, p.shrunk_error));
    return text;
}

}  // namespace

// "K/N", as --shard spells it.
void map_json(json_io& io, shard_spec& shard) {
    io.name(
        shard, [](const shard_spec& s) { return s.text(); },
        [](std::string_view text) -> std::optional<shard_spec> {
            try {
                return parse_shard(text);
            } catch (const input_error&) {
                return std::nullopt;
            }
        },
        "a shard K/N");
}

void map_json(json_io& io, hunt_objective& o) {
    io.name(o, hunt_objective_name, hunt_objective_from_name, "an objective");
}

void map_json(json_io& io, hunt_strategy& s) { io.name(s, hunt_strategy_name, hunt_strategy_from_name, "a strategy"); }

static void map_json(json_io& io, hunt_disagreement& d) {
    io.field("evaluation", d.evaluation);
    io.field("verdict", d.verdict);
    io.field("case", d.case_line);
}

static void map_json(json_io& io, hunt_run& r) {
    io.field("shard", r.shard);
    io.field("search_seed", r.search_seed);
    io.field("evaluations", r.evaluations);
    io.field("starts", r.starts);
    io.field("shrink_evaluations", r.shrink_evaluations);
    io.decimal_field("seconds", r.seconds);
    io.field("disagreements", r.disagreements);
    io.optional_field("first_disagreement", r.first_disagreement);
}

void map_json(json_io& io, hunt_record& h) {
    io.field("format", h.format);
    if (io.reading() && h.format != hunt_file_format)
        io.fail("format", fmt::format("{}: not a '{}' hunt line (written by another rayverify?)",
                                      json_io::quoted(h.format), hunt_file_format));
    io.field("build", h.build);
    io.field("command", h.command);
    io.field("target", h.target);
    io.field("objective", h.objective);
    io.field("rounding_only", h.rounding_only);
    io.field("strategy", h.strategy);
    io.field("family", h.family);
    io.field("seed", h.seed);
    io.optional_field("start_corpus", h.start_corpus);
    io.field("shards", h.shards);
    io.field("runs", h.runs);
    if (!io.reading()) return;
    if (h.runs.empty()) io.fail("runs", "is empty");
    for (std::size_t i = 0; i < h.runs.size(); ++i)
        if (h.runs[i].shard.count != h.shards)
            io.fail(fmt::format("runs[{}].shard", i),
                    fmt::format("is {}, a shard of a hunt of {}, not of {}", h.runs[i].shard.text(),
                                h.runs[i].shard.count, h.shards));
}

void map_json(json_io& io, hunt_find_provenance& p) {
    io.field("shard", p.shard);
    io.field("search_seed", p.search_seed);
    io.field("evaluation", p.evaluation);
    io.decimal_field("seconds", p.seconds);
    io.field("start", p.start);
    io.field("verdict", p.verdict);
    io.field("error", p.error);
    io.field("detail", p.detail);
    io.field("found_bits", p.found_bits);
    io.field("shrunk_verdict", p.shrunk_verdict);
    io.field("shrunk_error", p.shrunk_error);
    io.field("shrunk_bits", p.shrunk_bits);
    io.optional_field("inputs_changed", p.inputs_changed);
    io.optional_field("steps_from_start", p.steps_from_start);
}

hunt_file hunt_file_of(const hunt_result& result, const hunt_setting& setting) {
    const audit_target& target = *setting.target;
    const hunt_options& o = setting.options;
    hunt_file file;
    file.hunt.build = build_json();
    file.hunt.command = setting.command;
    file.hunt.target = target.label();
    file.hunt.objective = o.objective;
    file.hunt.rounding_only = o.rounding_only;
    file.hunt.strategy = o.strategy;
    file.hunt.family = setting.family;
    file.hunt.seed = setting.seed;
    if (setting.start_cases) file.hunt.start_corpus = setting.start_corpus;
    file.hunt.shards = setting.shard.count;
    file.hunt.runs = {{setting.shard, o.seed, result.evaluations, result.starts, result.shrink_evaluations,
                       result.seconds, result.disagreements, std::nullopt}};
    std::string id_stem = fmt::format("hunt-{}-{}-{}-{}-{}", target.subject.name, precision_name(target.prec),
                                      hunt_objective_name(o.objective), hunt_strategy_name(o.strategy), setting.seed);
    if (setting.shard.count > 1) id_stem += fmt::format("-shard{}of{}", setting.shard.index, setting.shard.count);
    const auto hunt_case = [&](std::string id, const ray_sphere<double>& geometry) {
        corpus_case c;
        c.id = std::move(id);
        c.family = "hunt_" + setting.family;
        if (setting.options.segments)
            set_segment_candidate(c, geometry);
        else
            c.geometry = geometry;
        return c;
    };
    const auto start_id = [&](std::uint64_t start_index) {
        const std::size_t global = setting.shard.global_index(start_index);
        return setting.start_cases ? (*setting.start_cases)[global % setting.start_cases->size()].id
                                   : generate_case(setting.family, setting.seed, global).id;
    };
    for (const hunt_find& f : result.finds) {
        const std::string id = fmt::format("{}-{}", id_stem, file.finds.size() + 1);
        hunt_find_provenance provenance{setting.shard, o.seed, f.evaluation, f.seconds, start_id(f.start_index),
                                        f.found_eval.verdict, f.found_eval.error, f.found_eval.detail,
                                        static_cast<std::size_t>(f.found_bits), f.shrunk_eval.verdict,
                                        f.shrunk_eval.error, static_cast<std::size_t>(f.shrunk_bits),
                                        std::nullopt, std::nullopt};
        if (o.shrink && o.shrink_toward_start) {
            provenance.inputs_changed = static_cast<std::size_t>(f.inputs_changed);
            provenance.steps_from_start = f.steps_from_start;
        }
        file.finds.push_back({std::move(provenance), hunt_case(id, f.shrunk), hunt_case(id + "-found", f.found)});
    }
    if (const auto& d = result.first_disagreement)
        file.hunt.runs[0].first_disagreement = {d->evaluation, d->found_eval.verdict,
                                                format_case_line(hunt_case(id_stem + "-disagreement", d->found))};
    return file;
}

std::string render_hunt_file(const hunt_file& file) {
    std::string text = corpus_header_comment() + '\n' + hunt_summary(file.hunt);
    text += fmt::format("{}{}\n", hunt_prefix, to_json_mapped(file.hunt).dump());
    std::size_t n = 0;
    for (const hunt_file_find& f : file.finds) {
        ++n;
        text += find_summary(file.hunt, f, n);
        text += fmt::format("{}{}\n", find_prefix, to_json_mapped(f.provenance).dump());
        text += format_case_line(f.shrunk) + '\n';
        text += fmt::format("# find {} as found, before shrinking:\n", n);
        text += format_case_line(f.found) + '\n';
    }
    return text;
}

bool looks_like_hunt_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    for (int i = 0; i < 12 && std::getline(in, line); ++i)
        if (line.starts_with(hunt_prefix)) return true;
    return false;
}

hunt_file read_hunt_file(const fs::path& path) {
    const std::string name = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw input_error(name, 0, "", "cannot open");
    std::stringstream whole;
    whole << in.rdbuf();
    const std::string contents = whole.str();

    hunt_file file;
    bool hunt_line_seen = false;
    std::vector<std::size_t> find_lines;
    for_each_text_line(name, contents, [&](std::size_t number, std::string_view line) {
        const bool hunt_line = line.starts_with(hunt_prefix), find_line = line.starts_with(find_prefix);
        if (!hunt_line && !find_line) return;
        const json value = parse_json_input(line.substr(hunt_prefix.size()), name, number);
        if (hunt_line) {
            if (hunt_line_seen) throw input_error(name, number, "rayverify-hunt", "a second hunt line");
            hunt_line_seen = true;
            file.hunt = from_json_mapped<hunt_record>(value, name, nullptr, number);
        } else {
            file.finds.push_back({from_json_mapped<hunt_find_provenance>(value, name, nullptr, number), {}, {}});
            find_lines.push_back(number);
        }
    });
    if (!hunt_line_seen)
        throw input_error(name, 0, "rayverify-hunt", "not the output of `rayverify hunt` (no rayverify-hunt line)");

    // Each find's two cases follow its line: shrunk, then as found.
    const std::vector<corpus_case> cases = parse_corpus(name, contents, false);
    if (cases.size() != 2 * file.finds.size())
        throw input_error(name, 0, "", fmt::format("{} finds but {} case lines: each find has two (shrunk, found)",
                                                   file.finds.size(), cases.size()));
    for (std::size_t i = 0; i < file.finds.size(); ++i) {
        file.finds[i].shrunk = cases[2 * i];
        file.finds[i].found = cases[2 * i + 1];
        const std::size_t next_find = i + 1 < find_lines.size() ? find_lines[i + 1] : SIZE_MAX;
        for (const corpus_case* c : {&cases[2 * i], &cases[2 * i + 1]}) {
            const std::size_t line = std::stoul(c->source.substr(c->source.rfind(':') + 1));
            if (line < find_lines[i] || line > next_find)
                throw input_error(name, line, "", fmt::format("a case line outside find {} (line {})", i + 1,
                                                              find_lines[i]));
        }
    }
    return file;
}


}  // namespace rayverify
