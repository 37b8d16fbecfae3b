#!/bin/bash
# Issue 43's goals for the samples: time to 1 % RMS candela error (the
# next-event study's "trace CPU s", which includes each step's far field,
# table error and estimate) of two builds, alternating the binaries in one
# run so that both see the same load.
#
#   bash scripts/time_to_error_ab.sh BASE_STUDY NEW_STUDY [ROUNDS] [SAMPLE...]
#
# BASE_STUDY, NEW_STUDY: gonio_next_event_study binaries (e.g. a worktree of
# 2e7d05e built with scripts/build.sh --target gonio_next_event_study, and
# build/benchmarks/gonio_next_event_study). Default: 2 rounds of bell,
# led-array, downlight and spotlight at a 2^23-photon reference. Prints the
# study's summary lines of each run (mode off, on, auto; `auto` is the
# default setting) headed by the binary and the load average.
set -euo pipefail
base=$1 new=$2 rounds=${3:-2}
shift $(( $# < 3 ? $# : 3 ))
samples=("$@")
[ ${#samples[@]} -gt 0 ] || samples=(bell led-array downlight spotlight)
for round in $(seq "$rounds"); do
  for s in "${samples[@]}"; do
    for b in "$base" "$new"; do
      echo "== round $round $s $b load $(cut -d' ' -f1-3 /proc/loadavg)"
      "$b" --reference-log2 23 --threads 2 --target 1 --sample "$s" 2>&1 | grep -E "^(sample|$s) +(mode|off|on|auto) "
    done
  done
done
