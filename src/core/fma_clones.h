// Hot double-word arithmetic built twice, for FMA hardware and without:
// std::fma (every two_prod and double-word product) is one instruction on
// the first and a library call on the other, and the loader picks the clone
// the CPU runs. Both compute the same bits: every operation is correctly
// rounded. Flattened, so that the double-word and expansion helpers a
// function calls are compiled into each clone. clang (the fuzz build)
// rejects flatten beside target_clones, so it only clones.
//
// For the oracle's filters and refinements and the judge's stability
// measures (compare/conditioning.cpp), in .cpp files only: a clone is a
// definition's attribute, never a header's.
#pragma once

#if defined(__clang__)
#define RAYVERIFY_CLONED_FOR_FMA __attribute__((target_clones("fma", "default")))
#else
#define RAYVERIFY_CLONED_FOR_FMA [[gnu::flatten]] __attribute__((target_clones("fma", "default")))
#endif
