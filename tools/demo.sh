#!/usr/bin/env bash
# README command 1: install what is missing, build, run the two-dumbbell demo.
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/install-deps.sh
cmake --preset release
cmake --build --preset release
./build/release/bin/noether run examples/dumbbells.yaml --force -o dumbbells.h5  # the demo replaces its own output
