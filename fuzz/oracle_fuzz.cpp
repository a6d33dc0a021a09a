// libFuzzer target: the exact oracle on arbitrary doubles, against the MPFR
// reference and its own invariants (see fuzz_checks.h).
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (const auto broken = rayverify::fuzz::check_oracle_input(data, size)) {
        std::fprintf(stderr, "oracle invariant violated: %s\n", broken->c_str());
        std::abort();
    }
    return 0;
}
