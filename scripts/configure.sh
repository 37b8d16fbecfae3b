#!/usr/bin/env bash
# Configures a build folder with Ninja: `scripts/configure.sh DIR [cmake
# arguments]`. Does nothing when DIR is configured already, unless the
# environment's GONIO_WERROR (1: warnings are errors, as CI builds) differs
# from DIR's cached GONIO_WERROR, or a Gonio option given here
# (-DGONIO_NAME=VALUE, e.g. -DGONIO_BUILD_TESTS=ON) differs from DIR's
# cache; then DIR is configured again with them (the cache keeps the rest,
# and what was not found before is looked for again).
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
  same=1
  for arg in "$@"; do
    if [[ "$arg" =~ ^-D(GONIO_[A-Z0-9_]+)(:[A-Z]+)?=(.*)$ ]]; then
      name=${BASH_REMATCH[1]}
      value=${BASH_REMATCH[3]}
      if ! grep -qE "^${name}:[A-Z]+=" "$cache" || [ "$(grep -E "^${name}:[A-Z]+=" "$cache" | head -1 | cut -d= -f2-)" != "$value" ]; then
        same=0
      fi
    fi
  done
  if [ "$same" = 1 ]; then exit 0; fi
fi
cmake -S . -B "$dir" -G Ninja "$@" -DGONIO_WERROR="$werror" >/dev/null
