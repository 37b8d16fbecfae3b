#!/usr/bin/env bash
# Installs what Gonio needs to build and test from Debian 12's packages, and
# nothing when everything is already there. Needs root (or sudo) only when
# something is missing.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config ccache
  help2man dpkg-dev file man-db
  libembree-dev libopenexr-dev libopenimageio-dev openimageio-tools
  libcgal-dev libtinygltf-dev libtbb-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin
  gnuplot-nox fonts-dejavu-core
  libcpp-httplib-dev chromium poppler-utils
  libpugixml-dev libzip-dev libxml2-utils libxxhash-dev
  clang-14 libfuzzer-14-dev llvm-14
  colord-data
  munge slurmctld slurmd slurm-client
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
  universal-ctags
  libocct-data-exchange-dev libocct-ocaf-dev libocct-modeling-algorithms-dev
  libocct-modeling-data-dev libocct-foundation-dev libocct-visualization-dev
  libtomlplusplus-dev libnlopt-cxx-dev
  freecad occt-draw libocct-draw-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# node and npm for the three.js client test (tests/client): any node with
# its npm will do (a NodeSource nodejs bundles npm, and Debian's npm package
# would conflict with it), so Debian's are installed only when none is there.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
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
