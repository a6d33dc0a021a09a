#include "corpus/case_stream.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <set>
#include <utility>

#include "core/input_error.h"
#include "core/spelling.h"
#include "corpus/corpus_io.h"
#include "corpus/generators.h"

namespace rayverify {

namespace fs = std::filesystem;

std::string shard_spec::text() const { return fmt::format("{}/{}", index, count); }

shard_spec parse_shard(std::string_view text) {
    const std::size_t slash = text.find('/');
    shard_spec shard;
    if (slash == std::string_view::npos || !parse_unsigned(text.substr(0, slash), shard.index) ||
        !parse_unsigned(text.substr(slash + 1), shard.count) || shard.count == 0 || shard.index == 0 ||
        shard.index > shard.count)
        throw input_error("", 0, "--shard",
                          fmt::format("'{}' is not K/N with 1 <= K <= N (shard K of N, e.g. 1/4), auto or auto/N", text));
    return shard;
}

std::string generate_spec::text() const { return fmt::format("{}:{}:{}", family, count, seed); }

generate_spec parse_generate_spec(std::string_view text) {
    generate_spec spec;
    const std::size_t first = text.find(':');
    const std::size_t second = first == std::string_view::npos ? first : text.find(':', first + 1);
    const auto bad = [&](const std::string& why) {
        return input_error("", 0, "--generate", fmt::format("'{}': {} (expected FAMILY:COUNT[:SEED])", text, why));
    };
    if (first == std::string_view::npos) throw bad("no count");
    spec.family = std::string(text.substr(0, first));
    const std::string_view count = text.substr(first + 1, second == std::string_view::npos ? second : second - first - 1);
    if (!parse_unsigned(count, spec.count) || spec.count == 0) throw bad("the count must be a whole number >= 1");
    if (second != std::string_view::npos && !parse_unsigned(text.substr(second + 1), spec.seed))
        throw bad("the seed must be a whole number");
    if (find_generator_family(spec.family) == nullptr) {
        std::string known;
        std::vector<std::string> names;
        for (const family_info& f : generator_families()) {
            known += (known.empty() ? "" : ", ") + std::string(f.name);
            names.emplace_back(f.name);
        }
        throw bad(fmt::format("unknown family '{}'{}; known: {}", spec.family, did_you_mean(spec.family, names), known));
    }
    return spec;
}

case_stream::case_stream(std::vector<fs::path> paths, shard_spec shard, std::size_t chunk)
    : shard_(shard), chunk_(chunk), paths_(std::move(paths)) {
    for (const fs::path& path : paths_) {
        reading_.arguments.push_back({list_corpus_argument(path), 0});
        for (const fs::path& file : reading_.arguments.back().argument.files) {
            files_.push_back(file);
            file_argument_.push_back(reading_.arguments.size() - 1);
        }
    }
}

case_stream::case_stream(std::vector<generate_spec> specs, shard_spec shard, std::size_t chunk)
    : shard_(shard), chunk_(chunk), specs_(std::move(specs)), generated_(true) {
    std::set<std::pair<std::string, std::uint64_t>> seen;
    for (const generate_spec& s : specs_) {
        if (!seen.insert({s.family, s.seed}).second)
            throw input_error("", 0, "--generate",
                              fmt::format("{} with seed {} twice: the cases (and their ids) would repeat", s.family,
                                          s.seed));
        fingerprint_.add_text(fmt::format("{} v{};", s.text(), find_generator_family(s.family)->version));
    }
}

void case_fingerprint::add_text(std::string_view text) { digest_.add(text); }

void case_fingerprint::add(const corpus_case& c) {
    digest_.add(c.id.data(), c.id.size() + 1);
    digest_.add(c.family.data(), c.family.size() + 1);
    const double inputs[10] = {c.geometry.origin.x,    c.geometry.origin.y,    c.geometry.origin.z,
                               c.geometry.direction.x, c.geometry.direction.y, c.geometry.direction.z,
                               c.geometry.centre.x,    c.geometry.centre.y,    c.geometry.centre.z,
                               c.geometry.radius};
    digest_.add(inputs, sizeof inputs);
    for (const std::optional<double>& bound : {c.tmin, c.tmax}) {
        const std::uint64_t bits = bound ? std::bit_cast<std::uint64_t>(*bound) : 0x7ff8dead0000beefULL;
        digest_.add(&bits, sizeof bits);
    }
    if (c.segment_end) {  // a segment's p1 (its direction above is p1 - p0 rounded); rays digest as before
        const double end[4] = {std::bit_cast<double>(0x7ff8dead5e600000ULL), c.segment_end->x, c.segment_end->y,
                               c.segment_end->z};
        digest_.add(end, sizeof end);
    }
}

std::string case_fingerprint::text() const { return digest_.text(); }

bool case_stream::next(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
    return generated_ ? next_generated(cases, indices) : next_from_files(cases, indices);
}

bool case_stream::next_from_files(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
    while (cases.size() < chunk_) {
        if (position_ == current_.size()) {
            if (next_file_ == files_.size()) break;
            current_ = read_corpus_file(files_[next_file_]);  // one file at a time (each at most 64 MiB)
            reading_.arguments[file_argument_[next_file_++]].cases += current_.size();
            position_ = 0;
            continue;
        }
        corpus_case& c = current_[position_++];
        if (!seen_ids_.insert(id_hash(c.id)))
            if (const std::optional<std::string> first = earlier_definition(c)) {
                const std::size_t colon = c.source.rfind(':');
                std::size_t line = 0;
                if (colon != std::string::npos) parse_unsigned(std::string_view(c.source).substr(colon + 1), line);
                throw input_error(c.source.substr(0, colon), line, "id",
                                  fmt::format("duplicate id '{}', first defined at {}", c.id, *first));
            }
        fingerprint_.add(c);  // every case of the input, owned or not
        const std::size_t index = total_++;
        if (!shard_.owns(index)) continue;
        cases.push_back(std::move(c));
        indices.push_back(index);
    }
    if (!cases.empty()) return true;
    if (total_ == 0) {
        std::string names;
        for (const auto& path : paths_) names += (names.empty() ? "" : ", ") + path.string();
        throw input_error(names, 0, "", "empty corpus: no cases found");
    }
    return false;
}

bool case_stream::id_hashes::insert(std::uint64_t hash) {
    hash += hash == 0;  // 0 marks an empty slot
    if (4 * (size_ + 1) > 3 * slots_.size()) {
        std::vector<std::uint64_t> old(std::max<std::size_t>(1024, 2 * slots_.size()), 0);
        old.swap(slots_);
        size_ = 0;
        for (std::uint64_t h : old)
            if (h != 0) insert(h);
    }
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash & mask;; i = (i + 1) & mask) {
        if (slots_[i] == hash) return false;
        if (slots_[i] == 0) {
            slots_[i] = hash;
            ++size_;
            return true;
        }
    }
}

std::optional<std::string> case_stream::earlier_definition(const corpus_case& c) const {
    // Within the file being read, ids are unique (read_corpus_file checks); the
    // files before it are read again (rare: a real duplicate is an error).
    for (std::size_t f = 0; f + 1 < next_file_; ++f)
        for (const corpus_case& earlier : read_corpus_file(files_[f]))
            if (earlier.id == c.id) return earlier.source;
    return std::nullopt;
}

bool case_stream::next_generated(std::vector<corpus_case>& cases, std::vector<std::size_t>& indices) {
    while (cases.size() < chunk_ && spec_ < specs_.size()) {
        const generate_spec& spec = specs_[spec_];
        const std::size_t offset = total_;  // global index of the spec's first case
        // The first local index at or after spec_position_ that this shard owns.
        std::size_t i = spec_position_;
        const std::size_t wanted = shard_.index - 1;
        i += (wanted + shard_.count - (offset + i) % shard_.count) % shard_.count;
        std::vector<std::size_t> local;
        for (; i < spec.count && cases.size() + local.size() < chunk_; i += shard_.count) {
            local.push_back(i);
            indices.push_back(offset + i);
        }
        append_generated_cases(spec.family, spec.seed, local, cases);
        spec_position_ = std::min(i, spec.count);
        if (spec_position_ == spec.count) {
            total_ += spec.count;
            ++spec_;
            spec_position_ = 0;
        }
    }
    return !cases.empty();
}

}  // namespace rayverify
