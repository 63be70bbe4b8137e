#!/usr/bin/env bash
# The Debian package, end to end (ctest -R package_deb): cpack -G DEB from the
# build tree into a scratch directory, then its control fields and contents
# (dpkg-deb --info / --contents), then the package extracted into a scratch
# root: its cubecal runs, its Python module imports and computes.
#
#   tests/package_check.sh BUILD_DIR VERSION
#
# Each failed check prints one line "package_deb: FAIL: ..." and exits 1; the
# scratch directory is then kept and its path printed.
set -euo pipefail

if [[ $# -ne 2 ]]; then
  echo "usage: $0 BUILD_DIR VERSION" >&2
  exit 2
fi
build=$(cd "$1" && pwd)
version=$2

scratch=$(mktemp -d "${TMPDIR:-/tmp}/cubecal-package.XXXXXX")
keep=1
trap 'if [[ $keep -eq 0 ]]; then rm -rf "$scratch"; else echo "package_deb: scratch directory kept: $scratch" >&2; fi' EXIT

fail() {
  echo "package_deb: FAIL: $*" >&2
  exit 1
}

for tool in cpack dpkg-deb dpkg; do
  command -v "$tool" >/dev/null || fail "$tool not found (scripts/install-deps.sh installs cmake and dpkg-dev)"
done
[[ -f "$build/CPackConfig.cmake" ]] || fail "no CPackConfig.cmake in $build (configure with cmake first)"

# --- The package --------------------------------------------------------------
arch=$(dpkg --print-architecture)
if ! (cd "$build" && cpack -G DEB -B "$scratch/cpack" --config "$build/CPackConfig.cmake") >"$scratch/cpack.log" 2>&1; then
  tail -n 30 "$scratch/cpack.log" >&2
  fail "cpack -G DEB failed (log: $scratch/cpack.log)"
fi
deb="$scratch/cpack/cubecal_${version}_${arch}.deb"
[[ -f "$deb" ]] || fail "cpack wrote no cubecal_${version}_${arch}.deb (found: $(cd "$scratch/cpack" && ls -- *.deb 2>/dev/null | tr '\n' ' '))"
size=$(stat -c %s "$deb")
echo "package_deb: $(basename "$deb"): $size bytes ($(numfmt --to=iec --suffix=B "$size"))"

# --- Control fields ---------------------------------------------------------------
dpkg-deb --info "$deb" >"$scratch/info.txt" || fail "dpkg-deb --info cannot read $(basename "$deb")"
field() { dpkg-deb --field "$deb" "$1"; }
[[ "$(field Package)" == cubecal ]] || fail "Package is '$(field Package)', not cubecal"
[[ "$(field Version)" == "$version" ]] || fail "Version is '$(field Version)', not $version"
[[ "$(field Architecture)" == "$arch" ]] || fail "Architecture is '$(field Architecture)', not $arch"
[[ "$(field Section)" == science ]] || fail "Section is '$(field Section)', not science"
[[ -n "$(field Maintainer)" ]] || fail "no Maintainer field"
[[ "$(field Description | wc -l)" -gt 2 ]] || fail "the Description has no long description"
depends=$(field Depends)
# One name per entry: "libc6 (>= 2.34), python3-numpy" -> libc6 python3-numpy
depends_names=" $(echo "$depends" | tr ',|' '\n\n' | sed -E 's/^ *([^ (]+).*/\1/' | tr '\n' ' ') "
for dep in libc6 libstdc++6 python3 python3-numpy; do
  [[ "$depends_names" == *" $dep "* ]] || fail "Depends lacks $dep: $depends"
done
[[ "$(field Recommends)" == *gnuplot-nox* ]] || fail "Recommends lacks gnuplot-nox: '$(field Recommends)'"
echo "package_deb: Depends: $depends"
# The Python byte code is compiled on installation and removed before removal.
mkdir -p "$scratch/control"
dpkg-deb --control "$deb" "$scratch/control" || fail "dpkg-deb --control cannot read $(basename "$deb")"
grep -q "py3compile -p cubecal" "$scratch/control/postinst" 2>/dev/null || fail "no postinst running py3compile -p cubecal"
grep -q "py3clean -p cubecal" "$scratch/control/prerm" 2>/dev/null || fail "no prerm running py3clean -p cubecal"
sh -n "$scratch/control/postinst" && sh -n "$scratch/control/prerm" || fail "a maintainer script is not valid sh"

# --- Contents -----------------------------------------------------------------------
dpkg-deb --contents "$deb" >"$scratch/contents.txt" || fail "dpkg-deb --contents cannot read $(basename "$deb")"
# The path column (6th), without the leading "./"; files.txt: all but directories.
awk '{print $6}' "$scratch/contents.txt" | sed 's|^\./||' >"$scratch/paths.txt"
awk '$1 !~ /^d/ {print $6}' "$scratch/contents.txt" | sed 's|^\./||' >"$scratch/files.txt"
has() {  # has DESCRIPTION REGEX: one path of the package matches REGEX
  grep -Eq "^($2)\$" "$scratch/paths.txt" || fail "the package has no $1 (no path matching ^$2\$)"
}
libdir='usr/lib(/[a-z0-9_]+-linux-gnu[a-z0-9_]*)?'
has "cubecal binary" 'usr/bin/cubecal'
has "man page cubecal(1)" 'usr/share/man/man1/cubecal\.1\.gz'
has "man page cubecal-analyze(1)" 'usr/share/man/man1/cubecal-analyze\.1\.gz'
has "header stats/deviation.hpp" 'usr/include/cubecal/stats/deviation\.hpp'
has "umbrella header cubecal.hpp" 'usr/include/cubecal/cubecal\.hpp'
has "CMake config" "$libdir/cmake/cubecal/cubecalConfig\\.cmake"
has "CMake version file" "$libdir/cmake/cubecal/cubecalConfigVersion\\.cmake"
for layer in core io pipeline report; do
  has "static library libcubecal_$layer.a" "$libdir/libcubecal_$layer\\.a"
  has "CMake targets of $layer" "$libdir/cmake/cubecal/cubecal_${layer}Targets\\.cmake"
done
has "Python package (__init__.py)" 'usr/lib/python3\.[0-9]+/dist-packages/cubecal/__init__\.py'
has "Python extension (_cubecal*.so)" 'usr/lib/python3\.[0-9]+/dist-packages/cubecal/_cubecal[^/]*\.so'
has "README.md" 'usr/share/doc/cubecal/README\.md'
has "copyright file" 'usr/share/doc/cubecal/copyright'
outside=$(grep -Ev '^(usr|usr/.*|)$' "$scratch/paths.txt" || true)
[[ -z "$outside" ]] || fail "paths outside /usr: $(echo "$outside" | head -n 3 | tr '\n' ' ')"
# Files per directory (the headers counted under usr/include/cubecal).
echo "package_deb: $(wc -l <"$scratch/files.txt") files: $(awk '{ d = $0; sub(/\/[^\/]*$/, "", d)
    if (d ~ /^usr\/include\/cubecal\//) d = "usr/include/cubecal"; n[d]++ }
  END { for (d in n) printf "%s %d\n", d, n[d] }' "$scratch/files.txt" | sort | paste -sd, | sed 's/,/, /g')"

# --- The extracted package ----------------------------------------------------------
root="$scratch/root"
dpkg-deb -x "$deb" "$root" || fail "dpkg-deb -x cannot extract $(basename "$deb")"
bin="$root/usr/bin/cubecal"
[[ -x "$bin" ]] || fail "usr/bin/cubecal is not executable"
zcat "$root/usr/share/man/man1/cubecal.1.gz" >"$scratch/cubecal.1" 2>/dev/null \
  || fail "usr/share/man/man1/cubecal.1.gz is not a valid gzip file"
grep -q '^\.TH CUBECAL ' "$scratch/cubecal.1" || fail "cubecal.1.gz has no .TH header"
grep -q '^analyze$' "$scratch/cubecal.1" || fail "cubecal.1.gz does not list the analyze subcommand"

work="$scratch/work"
mkdir -p "$work"
cd "$work"
"$bin" --help >help.txt 2>&1 || fail "usr/bin/cubecal --help exits non-zero: $(head -n 1 help.txt)"
grep -q 'simulate' help.txt || fail "usr/bin/cubecal --help does not list the simulate subcommand"
[[ "$("$bin" --version 2>&1)" == *"$version"* ]] || fail "usr/bin/cubecal --version does not say $version: $("$bin" --version 2>&1 | head -n 1)"
"$bin" simulate --preset sport-gyro --rate 100 --duration 10s --seed 1 --out gyro.csv >simulate.txt 2>&1 \
  || fail "usr/bin/cubecal simulate exits non-zero: $(tail -n 1 simulate.txt)"
[[ "$(wc -l <gyro.csv)" -gt 900 ]] || fail "usr/bin/cubecal simulate wrote $(wc -l <gyro.csv) lines for 10 s at 100 Hz"
"$bin" dev gyro.csv --format json --out dev.json >dev.txt 2>&1 || fail "usr/bin/cubecal dev exits non-zero: $(tail -n 1 dev.txt)"
/usr/bin/python3 - dev.json <<'EOF' || fail "usr/bin/cubecal dev wrote no finite positive deviations (dev.json)"
import json, math, sys
doc = json.load(open(sys.argv[1]))
devs = [d for c in doc["columns"] for d in c["dev"]]
sys.exit(0 if devs and all(math.isfinite(d) and d > 0 for d in devs) else 1)
EOF

# find_package(cubecal) on the extracted tree (configuration only).
mkdir -p "$work/consumer"
cat >"$work/consumer/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.20)
project(uses_cubecal LANGUAGES CXX)
find_package(cubecal REQUIRED)
get_target_property(lib cubecal::report IMPORTED_LOCATION_RELEASE)
file(WRITE "${CMAKE_BINARY_DIR}/found.txt" "${cubecal_DIR}\n${lib}\n")
EOF
cmake -S "$work/consumer" -B "$work/consumer/build" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=$root/usr" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >consumer.txt 2>&1 \
  || fail "find_package(cubecal) with CMAKE_PREFIX_PATH=<extracted>/usr fails: $(grep -m 1 -A 2 'Error' consumer.txt | tr '\n' ' ')"
while read -r found; do
  [[ "$found" == "$root"/usr/* ]] || fail "find_package(cubecal) on the extracted tree found $found, outside it"
done <"$work/consumer/build/found.txt"

# The module from the extracted tree only (-s: no user site; checked by its path).
pydir=$(cd "$root" && ls -d usr/lib/python3.*/dist-packages | head -n 1)
if ! PYTHONPATH="$root/$pydir" /usr/bin/python3 -s - "$root/$pydir" >python.txt 2>&1 <<'EOF'
import math, os, sys
import numpy as np
import cubecal
where = os.path.realpath(os.path.dirname(cubecal.__file__))
if not where.startswith(os.path.realpath(sys.argv[1]) + os.sep):
    sys.exit(f"cubecal imported from {where}, not from the package")
y = np.random.default_rng(1).normal(0.0, 1.0, 4096)
taus, devs, errs, ns = cubecal.oadev(y, rate=100.0, data_type="freq", taus="octave")
if len(devs) < 5 or not all(math.isfinite(d) and d > 0 for d in devs):
    sys.exit(f"cubecal.oadev gave {devs!r}")
print(f"cubecal {cubecal.__version__}: oadev of white noise at tau {taus[0]:g} s: {devs[0]:.4g}")
EOF
then
  fail "import cubecal from the package fails: $(tail -n 1 python.txt)"
fi
echo "package_deb: python3: $(tail -n 1 python.txt)"

echo "package_deb: ok: $(basename "$deb") ($(numfmt --to=iec --suffix=B "$size")) installs a working cubecal and Python module"
keep=0
