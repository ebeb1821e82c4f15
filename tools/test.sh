#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), then configures, builds and runs every test:
# Release with warnings as errors, then AddressSanitizer + UndefinedBehaviorSanitizer over the
# engine's in-process tests (the asan test preset leaves out the CLI's runs of the forest program and
# the GL tests' OSMesa and window backends, which repeat the EGL run's engine code: 20 of CI's
# minutes under the sanitizers).
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
