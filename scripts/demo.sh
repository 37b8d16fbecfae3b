#!/usr/bin/env bash
# README command (1): installs what is missing, builds, and runs the main job
# on the default sample. Until the simulator exists the main job is the
# photometric-file toolkit: `gonio info` on a sample curve, then `gonio
# convert` into the other format and back, and `gonio check` on the results.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh --target gonio
gonio=./build/tools/gonio
sample=samples/curves/wall_washer.ldt
out=out/demo
mkdir -p "$out"

"$gonio" --version
echo
echo "== gonio info $sample"
"$gonio" info "$sample"
echo
echo "== gonio convert $sample $out/wall_washer.ies"
"$gonio" convert "$sample" "$out/wall_washer.ies"
echo
echo "== gonio convert $out/wall_washer.ies $out/wall_washer_back.ldt"
"$gonio" convert "$out/wall_washer.ies" "$out/wall_washer_back.ldt"
echo
echo "== gonio info $out/wall_washer.ies --json (flux and LOR)"
"$gonio" info "$out/wall_washer.ies" --json | grep -E '^  "(flux_lm|lor|dff|max_cd)"'
echo
echo "== gonio check"
"$gonio" check "$sample" "$out/wall_washer.ies" "$out/wall_washer_back.ldt"
echo
echo "Outputs written to $(pwd)/$out:"
ls -l "$out"
