#!/usr/bin/env bash
# Installs the built project into a scratch prefix, builds examples/ against
# it with find_package(cubecal COMPONENTS core) while OpenMP and zlib are
# hidden from CMake (the core must not need them), and runs every example.
set -euo pipefail
BUILD_DIR=$1
EXAMPLES=$2
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cmake --install "$BUILD_DIR" --prefix "$WORK/prefix" >/dev/null
cmake -S "$EXAMPLES" -B "$WORK/build" -DCMAKE_PREFIX_PATH="$WORK/prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=ON -DCMAKE_DISABLE_FIND_PACKAGE_ZLIB=ON >/dev/null
cmake --build "$WORK/build" >/dev/null
"$WORK/build/gyro_noise"
