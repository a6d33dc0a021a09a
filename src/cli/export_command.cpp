// `rayverify corpus export`: the inputs of a corpus, generated families or a
// scene's (ray, sphere) pairs, in a form other programs read directly
// (corpus/exchange.h), for answers computed outside rayverify.
#include <fmt/format.h>

#include <algorithm>

#include "cli/commands.h"
#include "core/input_error.h"

namespace rayverify::cli {
namespace {

struct export_options {
    std::vector<std::string> corpus;
    std::vector<std::string> generate;
    std::string scene;
    std::string format;  // by the output's extension when empty
    std::string precision;
    std::string numbers = "decimal";
    std::string output;
};

int run_export(const export_options& o) {
    const std::filesystem::path output(o.output);
    std::optional<exchange_format> format =
        o.format.empty() ? exchange_format_of(output) : exchange_format_from_name(o.format);
    if (!format)
        throw input_error(o.output, 0, "--format",
                          "give --format csv|jsonl|npy, or an output ending in .csv, .jsonl or .npy");
    if (!o.scene.empty() && (!o.corpus.empty() || !o.generate.empty()))
        throw input_error("", 0, "--scene", "give one input: --scene, --corpus or --generate");

    // The outputs, declared before the work: never an input, appearing whole or not at all.
    run_outputs outputs;
    if (!o.scene.empty()) declare_inputs(outputs, {o.scene}, "--scene");
    declare_inputs(outputs, {o.corpus.begin(), o.corpus.end()}, "--corpus");
    output_file& out = outputs.file(output, "-o");
    output_file* companion = *format == exchange_format::npy ? &outputs.file(sidecar_of(output), "-o") : nullptr;

    // The cases, their count and fingerprint first (the header states them):
    // a scene's pairs in memory, a corpus or generated families streamed twice.
    std::optional<scene> sc;
    std::vector<corpus_case> pairs;
    std::optional<case_input> input;
    std::size_t count = 0;
    bool segments = false;  // some case is a segment: CSV and npy carry p1x..p1z
    std::string fingerprint;
    if (!o.scene.empty()) {
        sc = read_scene(o.scene);
        pairs = scene_cases(*sc);
        count = pairs.size();
        fingerprint = fingerprint_of(pairs);
    } else {
        input = select_input(o.corpus, o.generate);
        case_stream first = input->open();
        std::vector<corpus_case> cases;
        std::vector<std::size_t> indices;
        while (first.next(cases, indices)) {
            segments = segments || std::ranges::any_of(cases, &corpus_case::is_segment);
            cases.clear();
            indices.clear();
        }
        count = first.total();
        if (!first.reading().arguments.empty()) terminal::note("export: read " + first.reading().text());
        fingerprint = first.fingerprint();
    }
    const precision prec = !o.precision.empty() ? named_precision(o.precision)
                           : sc                 ? sc->prec
                                                : precision::binary64;
    const cases_header header{prec, exchange_fingerprint(fingerprint, prec), count,
                              o.numbers == "hex" ? number_style::hex : number_style::decimal, segments};

    case_writer writer(out.stream(), companion != nullptr ? &companion->stream() : nullptr, *format, header);
    if (sc) {
        for (const corpus_case& c : pairs) writer.write(c);
    } else {
        case_stream second = input->open();
        std::vector<corpus_case> cases;
        std::vector<std::size_t> indices;
        while (second.next(cases, indices)) {
            for (const corpus_case& c : cases) writer.write(c);
            cases.clear();
            indices.clear();
        }
    }
    writer.finish();
    fmt::print("wrote {} cases ({}, {}{}) to {}{}\nfingerprint {}\n", count, exchange_format_name(*format),
               precision_name(prec), *format == exchange_format::npy ? "" : ", " + o.numbers, o.output,
               companion != nullptr ? " and " + sidecar_of(output).string() : "", header.fingerprint);
    check_standard_output();
    outputs.commit();
    return exit_ok;
}

}  // namespace

command add_export_subcommand(CLI::App* corpus) {
    auto o = std::make_shared<export_options>();
    auto* sub = corpus->add_subcommand(
        "export", "Write the inputs of a corpus, generated families or a scene's (ray, sphere) pairs for a program "
                  "outside rayverify: CSV, JSON lines or NumPy .npy (with a .json companion: header and ids), "
                  "in float or double. Its answers come back with `rayverify audit --results` "
                  "(docs/other-languages.md)");
    sub->add_option("--corpus", o->corpus, "Corpus file (.txt or .csv) or directory; repeatable. Default: the shipped corpus");
    sub->add_option("--generate", o->generate, "Generated cases instead: FAMILY:COUNT[:SEED]; repeatable");
    sub->add_option("--scene", o->scene, "A scene file's (ray, sphere) pairs instead, ids '<ray>/<sphere>'");
    sub->add_option("--format", o->format, "csv, jsonl or npy (default: by the output's extension)")
        ->check(CLI::IsMember(every_exchange_format_name()));
    sub->add_option("--precision", o->precision,
                    "float or double: every value rounded to it, as an intersector in that precision receives it "
                    "(default: double; a scene's own precision)")
        ->check(CLI::IsMember(precision_names()));
    sub->add_option("--numbers", o->numbers,
                    "CSV and JSON lines: decimal (shortest round-trip in the precision) or hex (C99 hex floats)")
        ->check(CLI::IsMember({"decimal", "hex"}))
        ->capture_default_str();
    sub->add_option("-o,--output", o->output, "File to write (atomically); .npy also writes its .json companion")
        ->required();
    return {sub, [o] { return run_export(*o); }};
}

}  // namespace rayverify::cli
