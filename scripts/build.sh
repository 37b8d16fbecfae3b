#!/usr/bin/env bash
# Configures and builds Gonio in build/ (Release). Extra arguments go to the
# build step, e.g. `scripts/build.sh --target gonio`.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build build -j"$jobs" "$@"
