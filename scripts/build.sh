#!/usr/bin/env bash
# Configures Gonio in build/ (Release) and builds it. Extra arguments go
# to the build step, e.g. `scripts/build.sh --target gonio`. GONIO_WERROR=1
# in the environment builds with warnings as errors (scripts/configure.sh).
#
# build/ is configured with the test programs and benchmarks
# (GONIO_BUILD_TESTS, GONIO_BUILD_BENCHMARKS), which need GoogleTest and
# Google Benchmark (`scripts/setup.sh`, its full list). `scripts/build.sh
# --main ...` (README command 1, which installs only `scripts/setup.sh
# --main`) configures a build/ that has no configuration yet without them,
# and builds in an existing build/ as it is; the next plain
# `scripts/build.sh` (command 2) configures it again with them, finding then
# what setup.sh has installed since (OpenCASCADE, MPI, Python, npm,
# help2man), and builds the rest: the objects already built are kept, but
# for the few whose definitions follow what was found (the model loader
# with OpenCASCADE, the MPI driver).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
if [ "${1:-}" = --main ]; then
  shift
  if [ -f build/CMakeCache.txt ]; then
    bash scripts/configure.sh build -DCMAKE_BUILD_TYPE=Release
  else
    bash scripts/configure.sh build -DCMAKE_BUILD_TYPE=Release -DGONIO_BUILD_TESTS=OFF -DGONIO_BUILD_BENCHMARKS=OFF
  fi
else
  bash scripts/configure.sh build -DCMAKE_BUILD_TYPE=Release -DGONIO_BUILD_TESTS=ON -DGONIO_BUILD_BENCHMARKS=ON
fi
cmake --build build -j"$jobs" "$@"
