// What `rayverify hunt -o FILE` writes, and `rayverify merge` reads back: a
// corpus file (each find a pasteable case line, shrunk, then as found) whose
// comments tell a person what was searched and how each find came about, and
// carry the same as JSON for the merge: one `# rayverify-hunt {...}` line for
// the hunt and one `# rayverify-find {...}` line before each find's cases.
//
// A sharded hunt (`hunt --shard K/N`) is N independent hunts: shard K starts
// from the family's cases K−1, K−1+N, K−1+2N, … and searches with its own
// seed (compare/hunt.h, shard_search_seed). Merging the N files keeps the
// worst finds of all of them, each with its provenance (shard, search seed,
// evaluation, start case); a merged file merges again like a shard's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compare/hunt.h"
#include "core/ray_sphere_case.h"
#include "corpus/case_stream.h"
#include "corpus/json_mapping.h"

namespace rayverify {

inline constexpr const char* hunt_file_format = "rayverify-hunt 1";

// The first evaluation of a run whose answer disagreed with the exact one (an
// error objective has no error to rank it by, but it is a finding).
struct hunt_disagreement {
    std::size_t evaluation = 0;
    verdict_kind verdict = verdict_kind::agree;
    std::string case_line;  // pasteable
};

// One shard's search, as the hunt line records it.
struct hunt_run {
    shard_spec shard;
    std::uint64_t search_seed = 0;
    std::size_t evaluations = 0, starts = 0, shrink_evaluations = 0;
    double seconds = 0;
    std::size_t disagreements = 0;
    std::optional<hunt_disagreement> first_disagreement;
};

// The `# rayverify-hunt {...}` line: what was searched, and each shard's run
// (one in a shard's file, N in a merged one).
struct hunt_record {
    std::string format = hunt_file_format;
    nlohmann::ordered_json build;  // build_json(), compared as a whole
    std::string command;
    std::string target;  // "variant/precision"
    hunt_objective objective = hunt_objective::ulp;
    bool rounding_only = false;
    hunt_strategy strategy = hunt_strategy::search;
    std::string family;  // "corpus" when the start cases are the user's
    std::uint64_t seed = 0;
    // The corpus the start cases came from (hunt --corpus), as given.
    std::optional<std::string> start_corpus;
    std::size_t shards = 1;  // N
    std::vector<hunt_run> runs;
};

// A `# rayverify-find {...}` line: where a find came from and what it is.
struct hunt_find_provenance {
    shard_spec shard;
    std::uint64_t search_seed = 0;
    std::size_t evaluation = 0;
    double seconds = 0;
    std::string start;  // the start case's id
    verdict_kind verdict = verdict_kind::agree;
    double error = 0;
    std::string detail;
    std::size_t found_bits = 0;
    verdict_kind shrunk_verdict = verdict_kind::agree;
    double shrunk_error = 0;
    std::size_t shrunk_bits = 0;
    // Shrunk toward its start case (hunt --corpus): how many of the ten
    // inputs still differ from it, and by how many steps of the precision.
    std::optional<std::size_t> inputs_changed;
    std::optional<std::uint64_t> steps_from_start;
};

struct hunt_file_find {
    hunt_find_provenance provenance;
    corpus_case shrunk, found;
};

struct hunt_file {
    hunt_record hunt;
    std::vector<hunt_file_find> finds;
};

// The two lines' one mapping each (corpus/json_mapping.h): written by hunt
// and merge, read and checked by merge.
void map_json(json_io& io, hunt_record& hunt);
void map_json(json_io& io, hunt_objective& objective);
void map_json(json_io& io, hunt_strategy& strategy);
void map_json(json_io& io, shard_spec& shard);  // "K/N", as --shard spells it
void map_json(json_io& io, hunt_find_provenance& find);

// What a hunt was asked, beside its result, that its file records.
struct hunt_setting {
    std::string command;  // as recorded_command spells it
    const audit_target* target = nullptr;
    hunt_options options;       // options.seed: this shard's search seed
    std::string family;         // the start cases' generator family
    std::uint64_t seed = 0;     // the family's seed (--seed)
    shard_spec shard;
    // With hunt --corpus: the user's cases the hunt started from (start case
    // j is the one at the shard's global index j, cycling), and their file.
    const std::vector<corpus_case>* start_cases = nullptr;
    std::string start_corpus;
};

// The file of one hunt (one shard's): its record, with build_json(), and per
// find its provenance and two cases, the shrunk one id'd
// "hunt-VARIANT-PRECISION-OBJECTIVE-STRATEGY-SEED[-shardKofN]-K" and the one
// as found the same with "-found"; the run's first disagreement, if any, as a
// pasteable line.
hunt_file hunt_file_of(const hunt_result& result, const hunt_setting& setting);

// The file's text: the corpus header, the hunt's summary and JSON line, then
// per find its summary, JSON line and two case lines.
std::string render_hunt_file(const hunt_file& file);

// A find's error as the hunt's output says it: "3.2 ulp", or in the scene's
// length scale for scale_radius ("|t − t*|·|d| = 1e-15 r") and scale_distance.
std::string hunt_error_text(hunt_objective objective, double error);

// True when the file starts as render_hunt_file's output does (its first
// lines hold a `# rayverify-hunt ` line); false for anything else, including a
// file that cannot be read.
bool looks_like_hunt_file(const std::filesystem::path& path);

// Reads a hunt file back. Throws input_error naming file, line and field when
// it is not one (a malformed JSON line, a find without its two case lines, a
// format this build does not read).
hunt_file read_hunt_file(const std::filesystem::path& path);


}  // namespace rayverify
