#!/usr/bin/env bash
# README command (2): installs what is missing, builds, and runs every test:
# the photometry, io, io corpus and CAD suites under AddressSanitizer and
# UndefinedBehaviorSanitizer (clang), then the whole ctest suite on the Release build,
# then each fuzzer for $GONIO_FUZZ_SECONDS (default 60; scripts/fuzz.sh; 0
# leaves them out). GONIO_WERROR=1 in the environment (CI sets it) builds with
# warnings as errors; CI=true (CI sets it) fails the tests that would skip for
# missing data or tools.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)

bash scripts/setup.sh

echo "== sanitizer build (clang, AddressSanitizer + UndefinedBehaviorSanitizer)"
# clang, which the fuzzers need anyway: it compiles these suites at -O0 with
# both sanitizers in 40 % of GCC's time (docs/validation.md). A build-asan/
# configured with another compiler is configured afresh.
if [ -f build-asan/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++-14$' build-asan/CMakeCache.txt; then
  rm -rf build-asan
fi
bash scripts/configure.sh build-asan -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Debug -DGONIO_SANITIZE=ON \
  -DGONIO_BUILD_BENCHMARKS=OFF
suites=(gonio_photometry_tests gonio_io_tests gonio_io_corpus_tests gonio_cad_tests)
cmake --build build-asan -j"$jobs" --target "${suites[@]}"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# The corpus suite skips, saying so, where ../shared/corpus is absent (fails
# under CI=true). The suites run side by side, one per core, each into its
# log, printed when it ends.
run_suite() {
  local suite=$1 log="build-asan/$1.log" rc=0
  ./build-asan/tests/"$suite" --gtest_brief=1 >"$log" 2>&1 || rc=$?
  echo "== $suite (sanitizers): exit $rc"
  cat "$log"
  return "$rc"
}
export -f run_suite
printf '%s\n' "${suites[@]}" | xargs -P "$jobs" -I{} bash -c 'run_suite "$1"' _ {}

echo "== release build"
bash scripts/build.sh
echo "== ctest"
ctest --test-dir build --output-on-failure -j"$jobs"

fuzz_seconds=${GONIO_FUZZ_SECONDS:-60}
if [ "$fuzz_seconds" != 0 ]; then
  echo "== fuzz (${fuzz_seconds} s per reader)"
  bash scripts/fuzz.sh "$fuzz_seconds"
fi
