#!/usr/bin/env bash
# Configures a build folder with Ninja: `scripts/configure.sh DIR [cmake
# arguments]`. Does nothing when DIR is configured already, unless the
# environment's GONIO_WERROR (1: warnings are errors, as CI builds) differs
# from DIR's cached GONIO_WERROR; then DIR is configured again with it.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=$1
shift
werror=OFF
if [ "${GONIO_WERROR:-0}" = 1 ]; then
  werror=ON
fi
cache="$dir/CMakeCache.txt"
if [ -f "$cache" ] && grep -qx "GONIO_WERROR:BOOL=$werror" "$cache"; then
  exit 0
fi
cmake -S . -B "$dir" -G Ninja "$@" -DGONIO_WERROR="$werror" >/dev/null
