#include "report/hunt_file.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "core/input_error.h"
#include "corpus/case_stream.h"
#include "corpus/corpus_io.h"

namespace rayverify {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

std::string hunt_error_text(hunt_objective objective, double error) {
    switch (objective) {
        case hunt_objective::scale_radius: return fmt::format("|t − t*|·|d| = {:.3g} r", error);
        case hunt_objective::scale_distance: return fmt::format("|t − t*|·|d| = {:.3g} |o − c|", error);
        case hunt_objective::ulp:
        case hunt_objective::misclass: break;
    }
    return fmt::format("{:.3g} ulp", error);
}

namespace {

constexpr std::string_view hunt_prefix = "# rayverify-hunt ";
constexpr std::string_view find_prefix = "# rayverify-find ";

hunt_objective objective_of(const json& hunt) {
    const std::string name = hunt.at("objective").get<std::string>();
    const std::optional<hunt_objective> o = hunt_objective_from_name(name);
    if (!o) throw std::invalid_argument("unknown objective '" + name + "'");
    return *o;
}

// Under an error objective (ulp, scale_radius, scale_distance) the finds are errors found by search.
bool ulp_objective(const json& hunt) { return maximises_error(objective_of(hunt)); }

// "agree, 3.2 ulp" under an error objective; the verdict otherwise.
std::string outcome(const json& hunt, const json& verdict, const json& error) {
    return ulp_objective(hunt)
               ? fmt::format("agree, {}", hunt_error_text(objective_of(hunt), parse_exact_double(error.get<std::string>(),
                                                                                                "hunt file", 0, "error")))
               : verdict.get<std::string>();
}

std::string hunt_summary(const json& h) {
    std::string text = fmt::format("# rayverify hunt: {}, objective {}{}, strategy {}, start family {} (seed {})\n",
                                   h.at("target").get<std::string>(), h.at("objective").get<std::string>(),
                                   h.value("rounding_only", false) ? " (rounding causes only)" : "",
                                   h.at("strategy").get<std::string>(), h.at("family").get<std::string>(),
                                   h.at("seed").get<std::uint64_t>());
    text += fmt::format("# command: {}\n", h.at("command").get<std::string>());
    const json& runs = h.at("runs");
    std::uint64_t evaluations = 0, starts = 0, shrinking = 0;
    double seconds = 0;
    for (const json& r : runs) {
        evaluations += r.at("evaluations").get<std::uint64_t>();
        starts += r.at("starts").get<std::uint64_t>();
        shrinking += r.at("shrink_evaluations").get<std::uint64_t>();
        seconds += r.at("seconds").get<double>();
    }
    const std::size_t shards = h.at("shards").get<std::size_t>();
    if (runs.size() == 1 && shards > 1)
        text += fmt::format("# shard {} of the hunt, search seed {}\n", runs.at(0).at("shard").get<std::string>(),
                            runs.at(0).at("search_seed").get<std::uint64_t>());
    if (runs.size() > 1)
        text += fmt::format("# merged from {} shards, each an independent hunt with its own start cases and search "
                            "seed (listed in the rayverify-hunt line); totals over all of them:\n",
                            runs.size());
    text += fmt::format("# searched {} evaluations from {} start cases in {:.2f} s; {} shrinking evaluations\n",
                        evaluations, starts, seconds, shrinking);
    for (const json& r : runs)
        if (const auto d = r.find("first_disagreement"); d != r.end())
            text += fmt::format("# {}{} of {} evaluations disagreed with the exact answer; the first ({}) at evaluation "
                                "{}:\n#   {}\n",
                                runs.size() > 1 ? "shard " + r.at("shard").get<std::string>() + ": " : "",
                                r.at("disagreements").get<std::uint64_t>(), r.at("evaluations").get<std::uint64_t>(),
                                d->at("verdict").get<std::string>(), d->at("evaluation").get<std::uint64_t>(),
                                d->at("case").get<std::string>());
    if (ulp_objective(h))
        text += "# the error below is the largest FOUND BY SEARCH: a lower bound on the variant's maximum over all "
                "inputs, not the maximum\n";
    return text;
}

std::string find_summary(const json& h, const hunt_file_find& f, std::size_t n) {
    const json& p = f.provenance;
    std::string what = outcome(h, p.at("verdict"), p.at("error"));
    if (ulp_objective(h)) what += " (lower bound)";
    std::string from = fmt::format("searching from {}", p.at("start").get<std::string>());
    if (h.at("shards").get<std::size_t>() > 1)
        from += fmt::format(" in shard {} (search seed {})", p.at("shard").get<std::string>(),
                            p.at("search_seed").get<std::uint64_t>());
    std::string text = fmt::format("# find {}: {} at evaluation {} ({:.3f} s), {}\n", n, what,
                                   p.at("evaluation").get<std::uint64_t>(), p.at("seconds").get<double>(), from);
    if (const std::string detail = p.at("detail").get<std::string>(); !detail.empty())
        text += fmt::format("#   {}\n", detail);
    text += fmt::format("#   shrunk from {} to {} significant bits, still {}\n", p.at("found_bits").get<int>(),
                        p.at("shrunk_bits").get<int>(), outcome(h, p.at("shrunk_verdict"), p.at("shrunk_error")));
    return text;
}

}  // namespace

std::string render_hunt_file(const hunt_file& file) {
    std::string text = corpus_header_comment() + '\n' + hunt_summary(file.hunt);
    text += fmt::format("{}{}\n", hunt_prefix, file.hunt.dump());
    std::size_t n = 0;
    for (const hunt_file_find& f : file.finds) {
        ++n;
        text += find_summary(file.hunt, f, n);
        text += fmt::format("{}{}\n", find_prefix, f.provenance.dump());
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
    std::vector<std::size_t> find_lines;
    std::istringstream lines(contents);
    std::size_t number = 0;
    for (std::string line; std::getline(lines, line);) {
        ++number;
        const bool hunt_line = line.starts_with(hunt_prefix), find_line = line.starts_with(find_prefix);
        if (!hunt_line && !find_line) continue;
        json value;
        try {
            value = json::parse(line.substr(hunt_prefix.size()));
        } catch (const json::exception& e) {
            throw input_error(name, number, hunt_line ? "rayverify-hunt" : "rayverify-find",
                              fmt::format("not JSON: {}", e.what()));
        }
        if (hunt_line) {
            if (!file.hunt.is_null()) throw input_error(name, number, "rayverify-hunt", "a second hunt line");
            if (!value.is_object() || value.value("format", "") != hunt_file_format)
                throw input_error(name, number, "format",
                                  fmt::format("not a '{}' hunt line (written by another rayverify?)", hunt_file_format));
            file.hunt = std::move(value);
        } else {
            file.finds.push_back({std::move(value), {}, {}});
            find_lines.push_back(number);
        }
    }
    if (file.hunt.is_null())
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
    // Every field the file's text and the merge use is there, of its type.
    try {
        render_hunt_file(file);
        for (const json& run : file.hunt.at("runs")) parse_shard(run.at("shard").get<std::string>());
        for (const hunt_file_find& f : file.finds) parse_shard(f.provenance.at("shard").get<std::string>());
    } catch (const json::exception& e) {
        throw input_error(name, 0, "", fmt::format("not a hunt file: {}", e.what()));
    } catch (const input_error& e) {  // a shard or an error that does not parse
        throw input_error(name, 0, "", fmt::format("not a hunt file: {}", e.what()));
    }
    return file;
}

double find_error(const hunt_file_find& find) {
    return parse_exact_double(find.provenance.at("error").get<std::string>(), "hunt file", 0, "error");
}

}  // namespace rayverify
