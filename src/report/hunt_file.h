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

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compare/hunt.h"
#include "core/ray_sphere_case.h"

namespace rayverify {

inline constexpr const char* hunt_file_format = "rayverify-hunt 1";

struct hunt_file_find {
    // shard, search_seed, evaluation, seconds, start (the start case's id),
    // verdict, error (hex float), detail, found_bits; shrunk_verdict,
    // shrunk_error, shrunk_bits.
    nlohmann::ordered_json provenance;
    corpus_case shrunk, found;
};

struct hunt_file {
    // format, build, command, target, objective, strategy, family, seed,
    // shards (N), and runs: per shard, its shard, search_seed, evaluations,
    // starts, shrink_evaluations and seconds.
    nlohmann::ordered_json hunt;
    std::vector<hunt_file_find> finds;
};

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

// The error a find's JSON records, exactly (its hex float).
double find_error(const hunt_file_find& find);

}  // namespace rayverify
