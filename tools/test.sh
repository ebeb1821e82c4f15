#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), then configures, builds and runs every test:
# Release with warnings as errors, then AddressSanitizer + UndefinedBehaviorSanitizer.
# FOREST_TEST_PRESETS="release" limits the run to the presets named.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh

presets=${FOREST_TEST_PRESETS:-"release asan"}
for preset in $presets; do
  echo "== $preset: configure, build, test"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset"
  ctest --preset "$preset" -j"$(nproc)"
done
