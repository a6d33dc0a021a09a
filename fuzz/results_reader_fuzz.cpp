// libFuzzer target: the results-file readers (CSV, JSON lines, .npy with its
// companion) on arbitrary bytes (see results_fuzz_checks.h).
#include <cstdio>
#include <cstdlib>

#include "results_fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (const auto broken = rayverify::fuzz::check_results_reader_input(data, size)) {
        std::fprintf(stderr, "results reader invariant violated: %s\n", broken->c_str());
        std::abort();
    }
    return 0;
}
