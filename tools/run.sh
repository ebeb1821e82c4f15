#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (as root), builds the engine and runs the main job headless:
# the walkthrough of the default 5000-tree forest (data/scenes/forest.toml along
# data/paths/walk.toml, 1280x720, LiSPSM 2048², CHC++). Writes out/walkthrough/ (what an earlier
# run left there is replaced): every 10th frame, walkthrough.mp4 of every frame, a contact sheet, report.json and a summary
# on the screen. Extra arguments go to `forest walkthrough` (e.g. --gl=osmesa, --frames 100, --every 1,
# --scene FILE, --path FILE; `forest walkthrough --help` lists them).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target forest >/dev/null
./build/release/apps/forest info
./build/release/apps/forest walkthrough --out out/walkthrough "$@"
