#!/usr/bin/env bash
# Prints the table "Setup against model size" of docs/validation.md: the large generated
# models (gonio_make_samples --large) traced by `gonio simulate` for one
# iteration, first with an empty check cache (cold), then again (cached),
# with the setup times, the memory high-water mark and photons/s from each
# run's report.json.
#
#   scripts/scaling.sh [WORKDIR]      (default build/scaling; ~5 minutes,
#                                      2 GB at 10^7 triangles)
#
# Run it on a quiet machine: the times are wall-clock seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-build/scaling}
bash scripts/build.sh --target gonio gonio_make_samples >/dev/null
gonio=./build/tools/gonio
mkdir -p "$work"

# The last value of a key in a report.json (one key per line; for a key the
# iterations repeat, such as photons_per_s, the run's own, written after them).
key() { awk -v k="\"$2\":" '$1 == k { v = $2; sub(/,$/, "", v) } END { print v }' "$1"; }

# An empty run's memory: the process itself, subtracted per triangle below.
base_rss=0

row() {  # row KIND TRIANGLES [--no-instancing]
  local kind=$1 n=$2 flag=${3:-}
  local dir="$work/$kind-$n"
  [ -d "$dir" ] || ./build/samples/gonio_make_samples --large "$kind" "$n" "$dir" >/dev/null
  local model
  model=$(ls "$dir"/*/*.gltf)
  rm -rf "$dir/cache"
  local r=()
  for pass in cold cached; do
    $gonio simulate "$model" --out "$dir/out-$pass" --photons 200000 --iterations 1 --format ies \
      --flux-tolerance 1 --cache "$dir/cache" $flag >/dev/null 2>"$dir/log-$pass"
    r+=("$dir/out-$pass/report.json")
  done
  local label=$kind
  [ -n "$flag" ] && label="$kind, flat"
  awk -v label="$label" -v base="$base_rss" \
    -v pl="$(key "${r[0]}" triangles_placed)" -v un="$(key "${r[0]}" triangles_unique)" \
    -v l0="$(key "${r[0]}" load_s)" -v l1="$(key "${r[1]}" load_s)" \
    -v c0="$(key "${r[0]}" check_s)" -v c1="$(key "${r[1]}" check_s)" \
    -v b0="$(key "${r[0]}" bvh_s)" -v b1="$(key "${r[1]}" bvh_s)" \
    -v m0="$(key "${r[0]}" max_rss_bytes)" -v m1="$(key "${r[1]}" max_rss_bytes)" \
    -v p0="$(key "${r[0]}" photons_per_s)" -v p1="$(key "${r[1]}" photons_per_s)" \
    'BEGIN {
      m = (m0 > m1 ? m0 : m1);
      per = (un >= 100000) ? sprintf(" (%.0f)", (m - base) / un) : "";
      printf "| %s | %d (%d) | %.3f / %.3f | %.3f / %.3f | %.3f / %.3f | %.3f / %.3f | %.0f MB%s | %.2f / %.2f M |\n",
        label, pl, un, l0, l1, c0, c1, b0, b1, l0 + c0 + b0, l1 + c1 + b1, m / 1e6, per, p0 / 1e6, p1 / 1e6
    }'
}

# The empty run: the smallest model's process, less its few triangles.
dir="$work/base"
[ -d "$dir" ] || ./build/samples/gonio_make_samples --large faceted-reflector 100 "$dir" >/dev/null
$gonio simulate "$(ls "$dir"/*/*.gltf)" --out "$dir/out" --photons 200000 --iterations 1 --format ies \
  --flux-tolerance 1 --no-cache >/dev/null 2>&1
base_rss=$(key "$dir/out/report.json" max_rss_bytes)
echo "empty run: $((base_rss / 1000000)) MB"
echo "| model | triangles placed (unique) | load | checks | BVH | load + checks + BVH | peak memory (B/unique triangle) | photons/s |"
echo "|---|---|---|---|---|---|---|---|"
for n in 10000 100000 1000000 10000000; do row faceted-reflector $n; done
for n in 10000 100000 1000000 10000000; do row glass-part $n; done
for n in 10000 1000000 10000000 100000000; do row lens-array $n; done
for n in 1000000 10000000; do row lens-array $n --no-instancing; done
