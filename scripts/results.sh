#!/usr/bin/env bash
# Regenerates docs/results.md and its charts: `gonio bench` on the four
# sample luminaires, with importance-guided emission measured too, and the
# Sobol' sampler's raw and adaptive series beside the pseudo-random ones
# (`--sampler both`, bench's default).
#
#   scripts/results.sh [extra gonio bench options]
#
# The reference runs (2^29 photons each, a few minutes per sample on two
# cores, longer for the spotlight) are cached in docs/results/<sample>/ and
# reused while the model, the program version, the tracer (a hash of sim/)
# and the settings stay the same; only the SVG charts, series.csv,
# bench.json and the page are meant to be committed (docs/results/.gitignore
# keeps PNGs and the references out). Run it on a quiet machine: the page
# records the load average.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --target gonio gonio_samples
models=()
for name in bell downlight spotlight led-array; do
  models+=("build/samples/$name/$name.gltf")
done
./build/tools/gonio bench "${models[@]}" --out docs/results --page docs/results.md \
  --importance "$@"
