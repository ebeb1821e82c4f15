#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds the engine and runs the main job headless.
# For now the main job is one lit frame (forest render); the 5000-tree walkthrough replaces it
# when it lands. Extra arguments go to `forest render` (e.g. --gl=osmesa, --scene FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target forest >/dev/null
mkdir -p out
./build/release/apps/forest info
./build/release/apps/forest render --out out/render.png "$@"
