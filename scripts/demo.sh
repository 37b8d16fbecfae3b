#!/usr/bin/env bash
# README command (1): installs what is missing, builds, and runs the main job
# on the default sample.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh --target gonio
./build/tools/gonio --version
