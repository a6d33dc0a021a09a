// The hashes rayverify names inputs and seeds its generators by, each written
// once. FNV-1a, 64 bits (Fowler, Noll and Vo; the offset basis and prime of
// the specification, draft-eastlake-fnv), is the one hash of bytes.
// Case fingerprints, the digests of results files, plugins and a shard's
// per-case file, the generators' per-case seeds and the plots' sample of case
// ids are all this hash over their bytes; none is a cryptographic claim, only
// "the same bytes" (merge refuses shards whose digests differ).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace rayverify {

// The hash of bytes added piece by piece (one piece or many: the same bytes,
// the same hash).
class fnv1a_digest {
public:
    constexpr void add(std::string_view bytes) {
        for (const char c : bytes) hash_ = (hash_ ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
    }
    void add(const void* bytes, std::size_t n) { add(std::string_view(static_cast<const char*>(bytes), n)); }
    constexpr std::uint64_t value() const { return hash_; }
    // 16 lower-case hex digits (corpus/case_stream.h's is_fingerprint_text).
    std::string text() const {
        static constexpr char digits[] = "0123456789abcdef";
        std::string out(16, '0');
        for (int i = 0; i < 16; ++i) out[static_cast<std::size_t>(15 - i)] = digits[(hash_ >> (4 * i)) & 0xf];
        return out;
    }

private:
    std::uint64_t hash_ = 0xcbf29ce484222325ULL;  // the offset basis
};

// Adds the bytes of the file at `path` to `digest` (as far as it reads);
// false when it cannot be opened.
bool add_file_bytes(fnv1a_digest& digest, const std::filesystem::path& path);

constexpr std::uint64_t fnv1a(std::string_view bytes) {
    fnv1a_digest digest;
    digest.add(bytes);
    return digest.value();
}

// splitmix64's finaliser (Steele, Lea and Flood, "Fast splittable
// pseudorandom number generators", 2014): every input bit reaches every output bit.
constexpr std::uint64_t splitmix64_finalise(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// A case id's hash: FNV-1a, then the finaliser, so that ids differing only in
// their last characters spread over the whole range (a table indexed by the
// low bits, a sample kept by the smallest hashes).
constexpr std::uint64_t id_hash(std::string_view id) { return splitmix64_finalise(fnv1a(id)); }

}  // namespace rayverify
