// The corpus manifest: every shipped corpus file and how to rebuild it, so
// the shipped bytes can be regenerated and checked (`rayverify corpus regen`).
//
// Format (corpus/MANIFEST): one file a line, whitespace-separated,
//     file family count seed version
// `file` is relative to the manifest's directory, `version` is the family's
// generator version the file was made with; `#` starts a comment.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "corpus/generators.h"

namespace rayverify {

struct manifest_entry {
    std::string file;  // relative to the manifest's directory, '/'-separated
    std::string family;
    std::size_t count = 0;
    std::uint64_t seed = 0;
    int version = 0;
    std::size_t line = 0;  // line in the manifest, for messages
};

// Read a manifest. Throws input_error(path, line, field) for a malformed line,
// an unknown family, a version this build does not generate, a path that is
// absolute or leaves the directory, or a file listed twice.
std::vector<manifest_entry> read_manifest(const std::filesystem::path& path);

// The exact bytes `rayverify corpus generate --family F --count N --seed S`
// writes: the column header, three provenance comments, one line per case.
std::string generated_corpus_text(std::string_view family, std::size_t count, std::uint64_t seed);
// The same bytes handed to `write` in pieces of about 64 KiB, each case
// generated as its line is written: memory does not grow with the count.
void write_generated_corpus(std::string_view family, std::size_t count, std::uint64_t seed,
                            const std::function<void(std::string_view)>& write);

// Where two texts first differ, by line (1-based); nullopt when identical.
// A missing final line shows as an empty string.
struct first_difference {
    std::size_t line = 0;
    std::string expected;  // the line in `expected`
    std::string actual;    // the line in `actual`
};
std::optional<first_difference> compare_lines(const std::string& expected, const std::string& actual);

}  // namespace rayverify
