#!/usr/bin/env bash
# Installs the Debian 12 packages rayverify builds with. Idempotent: when all
# are present it only checks (a second run takes well under a second).
# Uses sudo only when not root.
set -euo pipefail

packages=(
  g++ cmake make               # toolchain
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev   # exact oracle (CGAL 5.5 is header-only)
  libgtest-dev                 # tests
  libcli11-dev nlohmann-json3-dev libfmt-dev        # CLI, JSON reports, formatting
  libbenchmark-dev python3-matplotlib               # rayverify bench (Google Benchmark), report plots
  python3-jsonschema           # tests: every JSON output against docs/schema/
  zsh groff-base               # tests: the generated zsh completion and man page are well formed
  libpng-dev                   # rayverify render (PNG images)
)
# tools/fuzz.sh: clang and its runtime libraries (libFuzzer, sanitizers).
[ "${1:-}" = "--fuzz" ] && packages+=(clang libclang-rt-14-dev)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
echo "setup: installing ${missing[*]}" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
