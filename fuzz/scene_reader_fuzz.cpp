// libFuzzer target: the scene reader and ray generator on arbitrary bytes (see scene_fuzz_checks.h).
#include <cstdio>
#include <cstdlib>

#include "scene_fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (const auto broken = rayverify::fuzz::check_scene_reader_input(data, size)) {
        std::fprintf(stderr, "scene reader invariant violated: %s\n", broken->c_str());
        std::abort();
    }
    return 0;
}
