#!/usr/bin/env bash
# Build the Debian package (CPack) from the build in BUILD_DIR (default build/),
# install it on this machine, check its declared dependencies, run the
# installed rayverify from another directory, and remove it again (dpkg -r).
# Needs root (CI runs as root). Usage: tools/deb_test.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=$(realpath "${1:-build}")
work=$(mktemp -d)
installed=0
cleanup() {
  if [ "$installed" = 1 ]; then dpkg -r rayverify >/dev/null; fi
  rm -rf "$work"
}
trap cleanup EXIT

if dpkg -s rayverify >/dev/null 2>&1; then
  echo "deb_test: a rayverify package is already installed; not touching it" >&2
  exit 2
fi
(cd "$build_dir" && cpack -G DEB -B "$work/package" >/dev/null)
deb=$(ls "$work"/package/rayverify_*.deb)
echo "deb_test: built $(basename "$deb")"

# Declared dependencies: the shared libraries the executable links (found by
# dpkg-shlibdeps), and python3-matplotlib recommended for the plots.
depends=$(dpkg-deb -f "$deb" Depends)
echo "deb_test: Depends: $depends"
for library in libc6 libstdc++6 libgmp10 libmpfr6 libpng16-16 libfmt9; do
  grep -q "\b$library\b" <<<"$depends" || { echo "deb_test: Depends lacks $library" >&2; exit 1; }
done
grep -q python3-matplotlib <<<"$(dpkg-deb -f "$deb" Recommends)" || { echo "deb_test: python3-matplotlib not recommended" >&2; exit 1; }
# No packaged data, header or CMake file points back into the source or build
# tree (the executable finds its corpus and plot script relative to itself).
dpkg-deb -x "$deb" "$work/contents"
if grep -rlF -e "$PWD" -e "$build_dir" "$work/contents/usr/share" "$work/contents/usr/include" \
     "$work/contents/usr/lib" --exclude='*.a'; then
  echo "deb_test: the files above name $PWD or $build_dir" >&2
  exit 1
fi

dpkg -i "$deb" >/dev/null
installed=1
mkdir "$work/elsewhere"
cd "$work/elsewhere"
command -v rayverify | grep -qx /usr/bin/rayverify
rayverify --version
# The engines' plugins are installed with the list that names them: every one
# the build made is available installed.
built=$("$build_dir/rayverify" engines | grep -c "Debian package .* available$" || true)
here=$(rayverify engines | grep -c "Debian package .* available$" || true)
[ "$built" = "$here" ] || { echo "deb_test: $here of the $built engine plugins built are available installed" >&2; exit 1; }
echo "deb_test: $here engine plugins available installed"
set +e
rayverify audit --generate near_tangent:2000 --variant naive --variant hearn_baker --summary --report report --plots
code=$?
set -e
[ "$code" = 1 ] || { echo "deb_test: rayverify audit exited $code (expected 1: findings)" >&2; exit 1; }
for file in report.json report.md summary.txt ulp_histograms.png; do
  [ -s "report/$file" ] || { echo "deb_test: report/$file missing" >&2; exit 1; }
done
rayverify corpus regen --check | grep -q "/usr/share/rayverify/corpus/MANIFEST"
[ -f /usr/share/man/man1/rayverify.1 ] && [ -f /usr/share/bash-completion/completions/rayverify ] &&
  [ -f /usr/share/zsh/vendor-completions/_rayverify ]
cd /
dpkg -r rayverify >/dev/null
installed=0
if [ -e /usr/bin/rayverify ]; then echo "deb_test: dpkg -r left /usr/bin/rayverify" >&2; exit 1; fi
echo "deb_test: installed, ran from another directory and removed: ok"
