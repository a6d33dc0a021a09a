// libFuzzer target: the gate's baseline reader and writer on arbitrary bytes (see baseline_fuzz_checks.h).
#include <cstdio>
#include <cstdlib>

#include "baseline_fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (const auto broken = rayverify::fuzz::check_baseline_reader_input(data, size)) {
        std::fprintf(stderr, "baseline reader invariant violated: %s\n", broken->c_str());
        std::abort();
    }
    return 0;
}
