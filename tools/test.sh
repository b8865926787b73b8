#!/usr/bin/env bash
# README command 2: install what is missing, build, run the test suite (slow tests excluded;
# `ctest --preset slow` runs those).
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/install-deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset release
