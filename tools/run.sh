#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds the engine and runs the main job headless.
# For now the main job is one lit frame of the default 5000-tree forest (forest render); the
# walkthrough replaces it when it lands. Extra arguments go to `forest render` (e.g. --gl=osmesa,
# --scene FILE overrides the scene).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target forest >/dev/null
mkdir -p out
./build/release/apps/forest info
scene=(--scene data/scenes/forest.toml)
for argument in "$@"; do [[ $argument == --scene* ]] && scene=(); done
./build/release/apps/forest render "${scene[@]}" --out out/render.png "$@"
