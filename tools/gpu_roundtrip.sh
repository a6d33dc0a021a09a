#!/usr/bin/env bash
# robust_sphere.h and the textbook quadratic on a real GPU, audited exactly:
# exports the shipped corpus and corpus/edge in float and double, builds
# examples/gpu/robust_gpu.cu with nvcc's defaults (-fmad=true) and with
# -fmad=false, runs both, and audits every results file they write.
# Needs nvcc and a CUDA GPU; rayverify built in build/ (tools/build.sh).
# Usage: tools/gpu_roundtrip.sh [OUTPUT_DIRECTORY]   (default: gpu_roundtrip)
# Prints one audit row per intersector, build and precision (read them against
# docs/robust_sphere.md: robust's rows have no misclassification, naive's do);
# exit 2 on a missing tool, else the first failing step's status.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-gpu_roundtrip}
nvcc=$(command -v nvcc || true)
[ -z "$nvcc" ] && [ -x /usr/local/cuda/bin/nvcc ] && nvcc=/usr/local/cuda/bin/nvcc
[ -n "$nvcc" ] || { echo "gpu_roundtrip: no nvcc" >&2; exit 2; }
[ -x build/rayverify ] || { echo "gpu_roundtrip: build/rayverify missing (tools/build.sh)" >&2; exit 2; }
mkdir -p "$out"
"$nvcc" --version | tail -2
"$nvcc" -O3 -std=c++20 -I src/intersectors examples/gpu/robust_gpu.cu -o "$out/robust_gpu"
"$nvcc" -O3 -std=c++20 -fmad=false -I src/intersectors examples/gpu/robust_gpu.cu -o "$out/robust_gpu_strict"
line='query=line_roots,reports_tangent=yes'
interval_nearest='query=nearest_hit,range=interval'
interval_any='query=any_hit,range=interval'
for precision in float double; do
  build/rayverify corpus export --corpus corpus --corpus corpus/edge --precision "$precision" -o "$out/cases_$precision.npy"
  for build in fmad strict; do
    program="$out/robust_gpu"; [ "$build" = strict ] && program="$out/robust_gpu_strict"
    dir="$out/${build}_$precision"
    mkdir -p "$dir"
    "$program" "$out/cases_$precision.npy" "$dir"
    for name in naive robust robust_nearest robust_any_hit robust_bounded; do
      case $name in
        robust_nearest) contract=$interval_nearest ;;
        robust_any_hit) contract=$interval_any ;;
        *) contract=$line ;;
      esac
      # exit 1 only means findings (naive has many); 2 or 3 is a failure
      rc=0
      build/rayverify audit --results "$dir/$name.npy" --contract "$contract" --name "gpu_${name}_$build" \
        --report "$dir/report_$name" > "$dir/$name.txt" || rc=$?
      [ "$rc" -le 1 ] || { cat "$dir/$name.txt" >&2; exit "$rc"; }
      sed -n 2p "$dir/$name.txt"
    done
  done
done
