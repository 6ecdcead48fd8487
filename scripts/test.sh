#!/usr/bin/env bash
# Installs the dependencies, builds detexture with its tests and runs the whole
# suite under ctest (its summary line closes the output).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
