#!/usr/bin/env bash
# Installs the Debian packages cubecal needs to build, test and benchmark.
# Only missing packages are installed; when everything is present this is a
# quiet no-op that takes well under a second.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libfmt-dev libcli11-dev nlohmann-json3-dev
  libboost-math-dev zlib1g-dev libbz2-dev liblz4-dev libzstd-dev libsqlite3-dev libhdf5-dev libfast-float-dev libeigen3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy gzip bc
  python3-pytest          # AllanTools' own test suite run against cubecal (scripts/allantools-suite.py)
  python3-scipy           # AllanTools (the peer `make bench` and the Python tests run) imports scipy.stats
  libfftw3-dev            # power spectral densities (cubecal psd): Welch on FFTW
  libserialport-dev       # cubecal record from serial devices
  pybind11-dev python3-dev   # the Python module (import cubecal)
  python3-build python3-setuptools python3-wheel python3-pip python3-venv   # the wheel (pyproject.toml: pip install ., python3 -m build) and its test
  python3-matplotlib      # examples/python: the paper's gyro figure
  python3-dask python3-distributed   # examples/python/fleet.py: one analysis per log on a Dask cluster
  help2man                # the man page of the .deb, generated from --help
  doxygen                 # the API reference (make docs) and its test
  python3-sphinx python3-myst-parser python3-numpydoc python3-sphinx-rtd-theme libjs-katex   # the documentation site (make docs, ctest docs.site)
  clang libclang-rt-14-dev libomp-dev   # fuzzers (make fuzz): libFuzzer, ASan, UBSan
  gnuplot-nox             # plots (SVG/PNG) of the report
  clang-format universal-ctags   # the format and architecture tests (scripts/check-format.sh, check-architecture.py)
  chromium                # browser test of report.html (headless)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: missing packages (${missing[*]}) and not root; install them with apt-get" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
