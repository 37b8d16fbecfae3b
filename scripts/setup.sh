#!/usr/bin/env bash
# Installs what Gonio needs from Debian 12's packages, and nothing when
# everything is already there. Needs root (or sudo) only when something is
# missing.
#
#   scripts/setup.sh --main   what README command (1), scripts/demo.sh, needs:
#                             the build tools, the libraries the Release
#                             build's configure step requires and `gonio`,
#                             gonio_png.so and the samples link, and the
#                             programs gonio runs for the main job's files
#   scripts/setup.sh [--all]  that and the rest, for command (2),
#                             scripts/test.sh: the tests, benchmarks, fuzzers,
#                             CAD, MPI, Python, the live page's client, PDF
#
# Each package is named once, in the first list that needs it; --all
# installs both. The sizes of each on a fresh Debian 12 are in
# docs/install.md ("What the two commands install").
set -euo pipefail

mode=all
case "${1:-}" in
  --main) mode=main ;;
  --all | "") mode=all ;;
  *)
    echo "setup: unknown option $1 (--main or --all)" >&2
    exit 2
    ;;
esac

# Command (1): cmake/GonioDependencies.cmake's REQUIRED packages (with
# openimageio-tools, which OpenImageIO's CMake package needs, and
# colord-data, whose CIE tables cmake/cie_cmf.cmake reads at configure
# time), the build tools, and gnuplot, which draws the intensity diagram
# `simulate` writes (fonts-dejavu-core for its text, as the .deb recommends).
main_packages=(
  cmake ninja-build g++ pkg-config ccache
  libembree-dev libopenexr-dev libopenimageio-dev openimageio-tools
  libcgal-dev libtinygltf-dev libtbb-dev nlohmann-json3-dev
  libcpp-httplib-dev libpugixml-dev libzip-dev libxxhash-dev libtomlplusplus-dev
  libnlopt-cxx-dev libpagmo-dev
  colord-data
  gnuplot-nox fonts-dejavu-core
)

# Command (2) also: GoogleTest and Google Benchmark (GONIO_BUILD_TESTS and
# GONIO_BUILD_BENCHMARKS), the optional parts of the build (MPI, OpenCASCADE
# for STEP and IGES, the Python module, man pages), the sanitizer and fuzz
# builds (clang, libFuzzer, llvm-symbolizer), and what the tests run: the
# package test (dpkg-dev, file, man-db), the PDF datasheet (chromium,
# poppler-utils), the CAD parts' writers (freecad, occt-draw), the Slurm
# scripts' cluster (munge, slurm), the Python tests, the code-size check.
test_packages=(
  help2man dpkg-dev file man-db
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin
  libxml2-utils
  chromium poppler-utils
  clang-14 libfuzzer-14-dev llvm-14
  munge slurmctld slurmd slurm-client
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
  universal-ctags
  libocct-data-exchange-dev libocct-ocaf-dev libocct-modeling-algorithms-dev
  libocct-modeling-data-dev libocct-foundation-dev libocct-visualization-dev
  freecad occt-draw libocct-draw-dev
)

packages=("${main_packages[@]}")
if [ "$mode" = all ]; then packages+=("${test_packages[@]}"); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# node and npm for the three.js client test (tests/client): any node with
# its npm will do (a NodeSource nodejs bundles npm, and Debian's npm package
# would conflict with it), so Debian's are installed only when none is there.
# Command (2) only.
if [ "$mode" = all ] && { ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; }; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
as_root=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
  else
    echo "setup: these packages are missing and installing them needs root: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
