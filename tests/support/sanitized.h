// Sweeps under the sanitizers. In the ASan+UBSan build (g++ defines
// __SANITIZE_ADDRESS__ there, clang++ 14 only answers
// __has_feature(address_sanitizer)) every instrumented operation costs several
// times more. The sweeps whose point is numeric agreement (the oracle's
// routes, the double-word bounds) run at full size in the default suite; in
// the sanitized suite they run one case in `sanitized_stride`, which still
// takes every code path they reach past the sanitizers in a fraction of the
// time (.ci/run runs both suites).
#pragma once

#include <algorithm>
#include <cstddef>

namespace rayverify::test_support {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool sanitized_build = true;
#elif defined(__has_feature)
inline constexpr bool sanitized_build = __has_feature(address_sanitizer);
#else
inline constexpr bool sanitized_build = false;
#endif

// One case in this many runs in the sanitized build; all of them otherwise.
inline constexpr std::size_t sanitized_stride = sanitized_build ? 8 : 1;

// `full` cases, or a share of them in the sanitized build (at least one).
constexpr std::size_t sweep_size(std::size_t full) { return std::max<std::size_t>(1, full / sanitized_stride); }

}  // namespace rayverify::test_support
