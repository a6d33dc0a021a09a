#!/usr/bin/env bash
# Which engine libraries can answer differently on another x86-64 CPU, read
# from their machine code: for every shared library an engine plugin of this
# build loads (beside the C and C++ run times), whether it asks the CPU what it
# can do (cpuid, xgetbv: a run-time dispatch), whether it holds reciprocal or
# square-root estimates (rcpps, rsqrtps, rcp14ps, ...: their last bits are the
# CPU's own, and vendors' differ), fused multiply-adds, AVX or AVX-512 code,
# GNU indirect functions, and which of the libm functions glibc itself
# dispatches by CPU (an FMA build where the CPU has FMA) it imports.
#
# Usage: tools/cpu_dependence.sh [MANIFEST]   (default build/engines/native_engines.json)
# Prints one row per library and a verdict; exit 0, or 2 when the manifest or
# a tool (objdump, readelf, ldd) is missing. docs/engines.md shows a run.
set -euo pipefail
manifest=${1:-build/engines/native_engines.json}
[ -f "$manifest" ] || { echo "cpu_dependence.sh: no manifest $manifest (build rayverify first)" >&2; exit 2; }
for tool in objdump readelf ldd; do
  command -v "$tool" >/dev/null || { echo "cpu_dependence.sh: $tool is not installed (binutils, libc-bin)" >&2; exit 2; }
done

# glibc 2.36's x86-64 libm functions with an FMA (or FMA4/AVX2) build picked at
# run time (sysdeps/x86_64/fpu/multiarch): their last bits may depend on the CPU.
dispatched_libm='^(acos|asin|atan|atan2|cos|cosf|exp|exp2f|expf|log|log2|log2f|logf|pow|powf|sin|sincosf|sinf|tan)$'

# Every library the built plugins load, less the C and C++ run times and what
# only a window system needs.
libraries=$(grep -o '"plugin": "[^"]*"' "$manifest" | sed 's/"plugin": "//; s/"$//' | while read -r plugin; do
  ldd "$plugin" | awk '$3 ~ /^\// {print $3}'
done | grep -v -E '/(libc|libm|libstdc\+\+|libgcc_s|ld-linux[^/]*|libpthread|libdl|librt|libX[a-z0-9]*|libxcb[^/]*|libGL[A-Za-z]*|libbsd|libmd)\.so' | sort -u)

printf '%-24s %6s %6s %9s %8s %8s %8s %6s  %s\n' library cpuid xgetbv estimates fma ymm zmm ifunc "dispatched libm imports"
dependent=0
for lib in $libraries; do
  # The instructions counted in one pass over the disassembly (embree's is
  # seven million lines): lines that hold a cpuid, an xgetbv, an estimate, a
  # fused multiply-add, a ymm or a zmm register.
  counts=$(objdump -d --no-show-raw-insn "$lib" | awk '
    /[ \t]cpuid([ \t]|$)/ { cpuid++ }
    /[ \t]xgetbv([ \t]|$)/ { xgetbv++ }
    /[ \t]v?(rcp|rsqrt)(14|28)?[ps]s[ \t]/ { estimates++ }
    /[ \t]vfn?m(add|sub)/ { fma++ }
    /%ymm/ { ymm++ }
    /%zmm/ { zmm++ }
    END { print cpuid + 0, xgetbv + 0, estimates + 0, fma + 0, ymm + 0, zmm + 0 }')
  read -r cpuid xgetbv estimates fma ymm zmm <<<"$counts"
  ifunc=$(readelf --dyn-syms -W "$lib" | grep -c ' IFUNC ' || true)
  libm=$(nm -D --undefined-only "$lib" 2>/dev/null | awk '{print $NF}' | sed 's/@.*//' | grep -E "$dispatched_libm" | tr '\n' ' ' | sed 's/ $//' || true)
  printf '%-24s %6s %6s %9s %8s %8s %8s %6s  %s\n' "$(basename "$lib")" "$cpuid" "$xgetbv" "$estimates" "$fma" "$ymm" "$zmm" "$ifunc" "${libm:--}"
  # Arithmetic that can differ: estimates, fused multiply-adds, or code picked
  # by the CPU among builds that use wider registers (or GNU indirect functions).
  if [ "$estimates" -gt 0 ] || [ "$fma" -gt 0 ] || [ "$ifunc" -gt 0 ] ||
     { [ "$((cpuid + xgetbv))" -gt 0 ] && [ "$((ymm + zmm))" -gt 0 ]; }; then
    dependent=$((dependent + 1))
    why=""
    [ "$((cpuid + xgetbv))" -gt 0 ] && why+="it picks code by the CPU (cpuid); "
    [ "$ifunc" -gt 0 ] && why+="it has indirect functions the loader picks by CPU; "
    [ "$estimates" -gt 0 ] && why+="its estimates are the CPU's; "
    [ "$fma" -gt 0 ] && why+="it has FMA code"
    echo "  -> may answer differently on another CPU: ${why%; }"
  elif [ "$((cpuid + xgetbv))" -gt 0 ]; then
    echo "  -> asks the CPU what it can do (cpuid) but holds no estimate, FMA or AVX code"
  elif [ -n "$libm" ]; then
    echo "  -> its own code is the same on every x86-64 CPU; the libm functions above are glibc's CPU-dispatched ones"
  fi
done
echo "$dependent of $(wc -w <<<"$libraries") libraries hold code whose answers can depend on the CPU"
