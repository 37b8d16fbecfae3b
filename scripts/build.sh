#!/usr/bin/env bash
# Configures Gonio in build/ (Release) once and builds it. Extra arguments go
# to the build step, e.g. `scripts/build.sh --target gonio`. GONIO_WERROR=1
# in the environment builds with warnings as errors (scripts/configure.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
bash scripts/configure.sh build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" "$@"
