#!/usr/bin/env bash
# Installs the Debian 12 packages rayverify builds with. Idempotent: when all
# are present it only checks (a second run takes well under a second).
# Uses sudo only when not root.
# Usage: tools/setup.sh [--fuzz] [--sanitize] [--slurm]
#   --fuzz      also clang for tools/fuzz.sh
#   --sanitize  also clang-14's sanitizer runtimes for tools/build.sh --sanitize
#   --slurm     also Slurm and MUNGE for the test labelled slurm (tools/slurm/local_cluster.sh);
#               their services are not started by the install (a private cluster is, by the test)
set -euo pipefail

packages=(
  g++ cmake make ninja-build   # toolchain (tools/build.sh builds with Ninja)
  lld                          # LLVM's linker: links the test executables in under half GNU ld's time
  ccache                       # a compiler cache: CMakeLists.txt uses it where it is installed
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev   # exact oracle (CGAL 5.5 is header-only)
  libgtest-dev                 # tests
  libcli11-dev nlohmann-json3-dev libfmt-dev        # CLI, JSON reports, formatting
  libbenchmark-dev python3-matplotlib               # rayverify bench (Google Benchmark), report plots
  zsh groff-base               # tests: the generated zsh completion and man page are well formed
  libpng-dev                   # rayverify render (PNG images)
  parallel                     # GNU parallel: the docs/scaling_out.md recipe a test runs
  python3-numpy nodejs         # tests: intersectors in NumPy and JavaScript audited through results files
  python3-jsonschema           # tests: every JSON output, exported case and answer against docs/schema/
  clang-14                     # tests: robust_sphere.h compiled for a GPU in CUDA mode, without the CUDA SDK
  # the engines' libraries audited as shipped (rayverify engines; docs/engines.md)
  libembree-dev libbullet-dev libode-dev libirrlicht-dev libopenscenegraph-dev
  pkg-config                   # finds ODE's and OpenSceneGraph's build flags
)
slurm=false
for option in "$@"; do
  case "$option" in
    --fuzz) packages+=(clang libclang-rt-14-dev) ;;  # tools/fuzz.sh: clang, libFuzzer, sanitizers
    --sanitize) packages+=(libclang-rt-14-dev) ;;  # tools/build.sh --sanitize: clang-14's ASan and UBSan runtimes
    --slurm) packages+=(slurm-wlm munge procps); slurm=true ;;  # procps: pgrep, ps for the cleanup checks
    *) echo "setup.sh: unknown option '$option' (--fuzz, --sanitize, --slurm)" >&2; exit 2 ;;
  esac
done

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

# The JavaScript engines audited as shipped: exactly the versions the committed
# package-lock.json pins, installed by `npm ci` into engines/js/node_modules
# (node and npm come with the machine; Debian's npm is not used). Skipped when
# node_modules already holds that lock's install.
install_javascript_engines() {
  local dir
  dir="$(cd "$(dirname "$0")/.." && pwd)/engines/js"
  [ -f "$dir/package-lock.json" ] || return 0
  if [ -f "$dir/node_modules/.package-lock.json" ] && [ "$dir/node_modules/.package-lock.json" -nt "$dir/package-lock.json" ]; then
    return 0
  fi
  command -v npm >/dev/null || { echo "setup: npm not found; the JavaScript engines need node 18 or later with npm" >&2; exit 2; }
  echo "setup: npm ci in $dir" >&2
  npm ci --prefix "$dir" --no-audit --no-fund --loglevel=error >&2
}

if [ ${#missing[@]} -eq 0 ]; then
  install_javascript_engines
  exit 0
fi

sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
# Installing munge and slurmd would start the machine's own daemons (from
# /etc/munge, /etc/slurm): Debian's policy-rc.d (exit 101) forbids that for
# the install, unless the machine already has a policy of its own.
policy=/usr/sbin/policy-rc.d
if $slurm && [ ! -e "$policy" ]; then
  trap '$sudo rm -f "$policy"' EXIT
  printf '#!/bin/sh\nexit 101\n' | $sudo tee "$policy" >/dev/null
  $sudo chmod 755 "$policy"
fi
echo "setup: installing ${missing[*]}" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
install_javascript_engines
