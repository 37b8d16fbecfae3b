#!/usr/bin/env bash
# README command (1): installs what the main job needs and is missing
# (scripts/setup.sh --main: the build tools and the libraries gonio needs,
# not what the tests need), builds gonio and the samples (scripts/build.sh
# --main: a new build/ without the test programs and benchmarks, which
# command (2) adds), and runs the main job:
# the bell sample (an opal pendant, samples/bell) traced end to end into the
# files a light-planning program reads, each read back and checked.
#
# 3 × 10⁶ photons (three iterations of 10⁶, a few seconds): the bell is
# rotationally symmetric and Gonio averages over the 72 C-planes, so two runs
# with different seeds differ by about 0.05 % RMS and at most 0.7 % (the
# zenith cap, the smallest bin) of the peak intensity — each file is within
# 1 % of the converged distribution.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --main
bash scripts/build.sh --main --target gonio gonio_samples
gonio=./build/tools/gonio
"$gonio" --version

out=out/bell
"$gonio" simulate build/samples/bell/bell.gltf --out "$out" --preview \
  --photons 1000000 --iterations 3

echo
echo "== gonio check on the written files"
"$gonio" check "$out/bell.ies" "$out/bell.ldt"

echo
echo "The bell's files, in $out/:"
echo "  $out/bell.ies           IES LM-63-2019 (computer simulation), 5° x 2.5° grid"
echo "  $out/bell.ldt           EULUMDAT, cd/klm, LORL, DFF and direct ratios"
echo "  $out/farfield.exr       far-field cube map (OpenEXR: Y in cd, flux, photons)"
echo "  $out/farfield-latlong.exr the same, equirectangular, for renderers"
echo "  $out/bell.svg           intensity diagram (C0-C180, C90-C270)"
echo "  $out/preview.png        unfolded cube, filtered preview"
echo "  $out/report.json        settings, energy ledger, each file's flux read back"
