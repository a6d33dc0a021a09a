// The cases of an audit as a stream: corpus files read one at a time, or
// generated cases made one by one, each with its global index in the whole
// input, so that memory does not grow with the number of cases. A shard K/N
// keeps the cases whose index i has i mod N = K − 1: the N shards of any input
// together hold every case exactly once, whatever the input is.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <optional>
#include <vector>

#include "core/hash.h"
#include "core/ray_sphere_case.h"
#include "corpus/corpus_io.h"

namespace rayverify {

// A whole number written in decimal digits only (no sign, no spaces), within T.
template <class T>
bool parse_unsigned(std::string_view text, T& value) {
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

struct shard_spec {
    std::size_t index = 1;  // K, 1 ≤ K ≤ N
    std::size_t count = 1;  // N
    bool owns(std::size_t case_index) const { return case_index % count == index - 1; }
    // How many of the indices 0 … total − 1 this shard owns.
    std::size_t size_of(std::size_t total) const { return total / count + (total % count >= index ? 1 : 0); }
    // The index in the whole input of this shard's case j (0, 1, ...): K − 1 + j·N.
    std::size_t global_index(std::size_t j) const { return index - 1 + j * count; }
    std::string text() const;  // "K/N"
};

// "K/N" with 1 ≤ K ≤ N; throws input_error (field "--shard") otherwise.
shard_spec parse_shard(std::string_view text);

// Cases of one generator family (corpus/generators.h), made on the fly.
struct generate_spec {
    std::string family;
    std::size_t count = 0;
    std::uint64_t seed = 1;
    std::string text() const;  // "FAMILY:COUNT:SEED"
};

// "FAMILY:COUNT[:SEED]" (seed 1 when absent, as `corpus generate`); throws
// input_error (field "--generate") for a malformed spec or an unknown family.
generate_spec parse_generate_spec(std::string_view text);

// 16 hex digits identifying an input: FNV-1a (core/hash.h) over every case in order (id,
// family, the ten inputs and the interval, as their bytes), or over texts
// that name it (a generated family and its version).
class case_fingerprint {
public:
    void add(const corpus_case& c);
    void add_text(std::string_view text);
    std::string text() const;

private:
    fnv1a_digest digest_;
};

// Whether text is written as case_fingerprint::text() writes a fingerprint or
// a file's digest: 16 lower-case hex digits.
inline bool is_fingerprint_text(std::string_view text) {
    return text.size() == 16 && text.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

class case_stream {
public:
    static constexpr std::size_t default_chunk = 4096;

    // Corpus files and directories, in the order given (as read_corpus reads
    // them: the same errors, including duplicate ids across files and an
    // empty corpus, the latter raised when the stream ends).
    case_stream(std::vector<std::filesystem::path> paths, shard_spec shard, std::size_t chunk = default_chunk);
    // Generated families one after the other. Two specs with the same family
    // and seed would repeat ids: an input_error.
    case_stream(std::vector<generate_spec> specs, shard_spec shard, std::size_t chunk = default_chunk);

    // Fills up to `chunk` cases of this shard with their global indices;
    // false when the input is exhausted.
    bool next(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices);

    // Bytes held for the duplicate-id check (corpus files; 0 for generated cases).
    std::size_t id_check_bytes() const { return seen_ids_.bytes(); }
    // Cases of the whole input (every shard's) passed so far; once next()
    // returned false, the input's size.
    std::size_t total() const { return total_; }
    // 16 hex digits identifying the whole input passed so far: a hash of every
    // case (id, family, inputs, interval) for files; of the specs and each
    // family's generator version for generated cases.
    std::string fingerprint() const { return fingerprint_.text(); }
    // Each corpus argument's files and the cases read from them so far
    // (complete once next() returned false); empty for generated cases.
    const corpus_reading& reading() const { return reading_; }

private:
    bool next_from_files(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices);
    bool next_generated(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices);

    shard_spec shard_;
    std::size_t chunk_;
    std::size_t total_ = 0;
    case_fingerprint fingerprint_;
    // Files.
    std::vector<std::filesystem::path> paths_;
    std::vector<std::filesystem::path> files_;
    std::vector<std::size_t> file_argument_;  // files_[i] came from reading_.arguments[file_argument_[i]]
    corpus_reading reading_;
    std::size_t next_file_ = 0;
    std::vector<corpus_case> current_;
    std::size_t position_ = 0;
    // The ids seen so far, as 64-bit hashes: 8 bytes a slot, at most 3/4 of
    // the slots used, so at most 21.4 bytes per case whatever the ids' length
    // (docs/outputs.md). A hash seen before is checked exactly by finding the
    // id in the files read so far, so a collision never reports a duplicate.
    class id_hashes {
    public:
        bool insert(std::uint64_t hash);  // false when present already
        std::size_t bytes() const { return slots_.size() * sizeof(std::uint64_t); }

    private:
        std::vector<std::uint64_t> slots_;  // 0: empty
        std::size_t size_ = 0;
    };
    id_hashes seen_ids_;
    // The first definition of c.id among the cases read before it, if any (the exact re-check).
    std::optional<std::string> earlier_definition(const corpus_case& c) const;
    // Generated.
    std::vector<generate_spec> specs_;
    std::size_t spec_ = 0, spec_position_ = 0;  // next index within specs_[spec_] to consider
    bool generated_ = false;
};

}  // namespace rayverify
