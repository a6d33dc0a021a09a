#include "core/hash.h"

#include <array>
#include <fstream>

namespace rayverify {

bool add_file_bytes(fnv1a_digest& digest, const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::array<char, 1 << 16> buffer{};
    while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
        digest.add(buffer.data(), static_cast<std::size_t>(in.gcount()));
        if (!in) break;
    }
    return true;
}

}  // namespace rayverify
