#!/usr/bin/env bash
# README command 1: install what is missing, build, run the two-dumbbell demo.
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/install-deps.sh
cmake --preset release
# Only what the demo runs: the driver and the two plugins the scene names (tools/test.sh
# builds everything).
cmake --build --preset release --target noether noether-plugin-sphere-cluster noether-plugin-lgvi
./build/release/bin/noether run examples/dumbbells.yaml --force -o dumbbells.h5  # the demo replaces its own output
