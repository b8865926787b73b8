#!/usr/bin/env bash
# The sanitizer job of CI (.ci/run): builds everything with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer (float-cast-overflow included, every report fatal) in
# build/sanitize, and runs the default tests there (slow, install, docs, scale and view tests
# excluded: CMakePresets.json).
set -euo pipefail
cd "$(dirname "$0")/.."
./tools/install-deps.sh --sanitize
cmake --preset sanitize
cmake --build --preset sanitize
ctest --preset sanitize
