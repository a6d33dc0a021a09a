#!/usr/bin/env bash
# Set up packages, configure and build. Usage: tools/build.sh [--sanitize]
# The default build goes to build/, the ASan+UBSan build to build-sanitize/.
set -euo pipefail
cd "$(dirname "$0")/.."

build_dir=build
# CMake's default is Release; the development build keeps RelWithDebInfo's -O2
# (the figures and timings in docs/ and the gate baseline were measured with it)
# with line tables only (-g1): a crash in a test or a plugin still gets a
# backtrace with files and lines, and debug information never changes the code
# GCC generates. Full debug information (-g) is copied into every test
# executable that links the library: it made the build more than twice the
# size and filled a CI machine's disk (docs/testing.md).
cmake_args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
            "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG")
setup_options=()
if [ "${1:-}" = "--sanitize" ]; then
  build_dir=build-sanitize
  setup_options=(--sanitize)
  # Line tables (-g1) are all a sanitizer's report needs. -O1, as the
  # sanitizers' own documentation suggests: every check stays (fewer are
  # optimised away), and it compiles in about half -O2's time (docs/testing.md).
  # Built by clang++ (the default build is g++'s): it compiles this build in
  # about 70% of g++'s time, and a second compiler reads every source the
  # suite runs (it found the generators' draws made in an order each compiler
  # chooses: corpora regenerated differently).
  cmake_args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAYVERIFY_SANITIZE=ON "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
              "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14)
  # A sanitizer build directory made by another compiler is made again.
  if [ -f "$build_dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++-14$' "$build_dir/CMakeCache.txt"; then
    echo "build.sh: $build_dir was configured with another compiler; configuring it again with clang++-14" >&2
    rm -rf "$build_dir"
  fi
fi

# Ninja schedules the whole build as one graph (Make's recursive makefiles
# wait at each directory's targets); a build directory made before keeps the
# generator it was made with.
[ -f "$build_dir/CMakeCache.txt" ] || cmake_args+=(-G Ninja)

tools/setup.sh "${setup_options[@]}"
cmake -S . -B "$build_dir" "${cmake_args[@]}" >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
