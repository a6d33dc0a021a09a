#!/usr/bin/env bash
# Set up packages, configure and build. Usage: tools/build.sh [--sanitize]
# The default build goes to build/, the ASan+UBSan build to build-sanitize/.
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
# CMake's default is Release; the development build keeps RelWithDebInfo (-O2 -g):
# the figures and timings in docs/ and the gate baseline were measured with it,
# and a crash in a test or a plugin gets a readable backtrace.
cmake_args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo)
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-sanitize
  # Line tables (-g1) are all a sanitizer's report needs; full debug info
  # costs compile and link time on every test file.
  cmake_args+=(-DRAYVERIFY_SANITIZE=ON "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
               "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG")
fi

tools/setup.sh
cmake -S . -B "$build_dir" "${cmake_args[@]}" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
