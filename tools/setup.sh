#!/usr/bin/env bash
# Installs every Debian 12 package the forest engine needs (run as root).
# Idempotent: prints nothing and touches nothing when everything is present.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config git python3
  # GL loader generator (glad 2) and headless / windowed GL
  python3-glad libegl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev libglfw3-dev xvfb xauth
  # math, meshes, images, ray tracing
  libglm-dev libopenmesh-dev libopenimageio-dev libembree-dev libmeshoptimizer-dev
  # a font for the labels of diagrams (OpenImageIO render_text)
  fonts-dejavu-core
  # file formats, command line, tests, benchmarks
  libtomlplusplus-dev nlohmann-json3-dev libcli11-dev libfmt-dev libgtest-dev libgmock-dev libbenchmark-dev
  # GL calls per frame (tools/gl-calls.sh, the ctest gl_calls_per_frame)
  apitrace
  # the walk as a video (walkthrough.mp4) and its test (ffprobe)
  ffmpeg
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

if [[ $(id -u) -ne 0 ]]; then
  echo "setup.sh: missing packages (${missing[*]}); run as root to install them" >&2
  exit 1
fi
echo "setup.sh: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup.sh: done"
