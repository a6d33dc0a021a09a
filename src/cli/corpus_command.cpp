#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/commands.h"
#include "core/input_error.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"
#include "corpus/manifest.h"

namespace rayverify::cli {
namespace {

namespace fs = std::filesystem;

struct generate_options {
    std::string family;
    std::size_t count = 500;
    std::uint64_t seed = 1;
    std::string output;
};

int generate(const generate_options& options) {
    if (find_generator_family(options.family) == nullptr)
        generate_family(options.family, 0, options.seed);  // throws the unknown-family error
    run_outputs outputs;
    output_file* file = options.output.empty() ? nullptr : &outputs.file(options.output, "-o");
    write_generated_corpus(options.family, options.count, options.seed, [&](std::string_view piece) {
        if (file == nullptr)
            std::fwrite(piece.data(), 1, piece.size(), stdout);
        else
            file->stream() << piece;
    });
    check_standard_output();
    outputs.commit();
    return exit_ok;
}

struct regen_options {
    bool check = false;
    std::string corpus_dir = default_corpus();
};

std::optional<std::string> read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

// Rebuild (or, with --check, compare) every file the manifest lists. Every
// entry is generated in full before anything is written, so a bad manifest
// leaves the corpus untouched.
int regen(const regen_options& options) {
    const fs::path dir(options.corpus_dir);
    const fs::path manifest = dir / "MANIFEST";
    const std::vector<manifest_entry> entries = read_manifest(manifest);
    if (entries.empty()) throw input_error(manifest.string(), 0, "", "the manifest lists no file");

    std::vector<std::string> texts;
    texts.reserve(entries.size());
    for (const manifest_entry& e : entries) texts.push_back(generated_corpus_text(e.family, e.count, e.seed));

    if (!options.check) {
        // Every file of the manifest replaced together, or none.
        run_outputs outputs;
        for (std::size_t i = 0; i < entries.size(); ++i) {
            const fs::path file = dir / entries[i].file;
            outputs.directory(file.parent_path(), "--corpus-dir");
            outputs.file(file, "--corpus-dir").stream() << texts[i];
            fmt::print("wrote {} ({} {}, {} cases, seed {})\n", file.string(), entries[i].family,
                       fmt::format("v{}", entries[i].version), entries[i].count, entries[i].seed);
        }
        check_standard_output();
        outputs.commit();
        return exit_ok;
    }

    std::size_t differing = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const fs::path file = dir / entries[i].file;
        const std::optional<std::string> committed = read_bytes(file);
        if (!committed) {
            ++differing;
            fmt::print("{}: missing (listed at {}:{})\n", file.string(), manifest.string(), entries[i].line);
            continue;
        }
        if (const auto diff = compare_lines(texts[i], *committed)) {
            ++differing;
            fmt::print("{}:{}: differs from what the manifest regenerates ({} --count {} --seed {})\n"
                       "  regenerated: {}\n  committed:   {}\n",
                       file.string(), diff->line, entries[i].family, entries[i].count, entries[i].seed,
                       diff->expected, diff->actual);
        }
    }
    if (differing > 0) {
        fmt::print("{} of {} corpus files differ from the manifest; `rayverify corpus regen` rebuilds them\n",
                   differing, entries.size());
        return exit_findings;
    }
    fmt::print("{} corpus files match {} byte for byte\n", entries.size(), manifest.string());
    return exit_ok;
}

}  // namespace

command add_corpus_command(CLI::App& app) {
    auto* sub = app.add_subcommand("corpus", "Work with case corpora");
    sub->require_subcommand(1);
    auto options = std::make_shared<generate_options>();
    auto* gen = sub->add_subcommand("generate", "Generate cases of one family, deterministically from the seed");
    std::string families;
    for (const family_info& f : generator_families()) families += fmt::format("\n  {:<22} {}", f.name, f.description);
    gen->add_option("--family", options->family, "Family to generate:" + families)->required();
    // A bound keeps a typo from exhausting memory; the file stays far below the reader's size limit.
    gen->add_option("--count", options->count, "Number of cases (1 to 100000)")
        ->capture_default_str()
        ->check(whole_number(1, 100000));
    gen->add_option("--seed", options->seed, "Seed")->check(whole_number(0))->capture_default_str();
    gen->add_option("-o,--output", options->output, "Write to this file (atomically) instead of stdout");

    auto regen_opts = std::make_shared<regen_options>();
    auto* re = sub->add_subcommand("regen", "Rebuild every corpus file listed in <corpus-dir>/MANIFEST; with "
                                            "--check, compare instead and exit 1 naming each file that differs and "
                                            "its first differing line");
    re->add_flag("--check", regen_opts->check, "Compare the regenerated bytes with the files; write nothing");
    re->add_option("--corpus-dir", regen_opts->corpus_dir, "Directory holding MANIFEST")->capture_default_str();
    const command exporting = add_export_subcommand(sub);
    return {sub, [options, regen_opts, re, exporting] {
                if (exporting.parser->parsed()) return exporting.run();
                return re->parsed() ? regen(*regen_opts) : generate(*options);
            }};
}

}  // namespace rayverify::cli
