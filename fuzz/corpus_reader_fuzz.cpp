// libFuzzer target: the corpus and CSV readers on arbitrary bytes (see fuzz_checks.h).
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (const auto broken = rayverify::fuzz::check_corpus_reader_input(data, size)) {
        std::fprintf(stderr, "corpus reader invariant violated: %s\n", broken->c_str());
        std::abort();
    }
    return 0;
}
