#!/usr/bin/env bash
# Installs ringlet's build and test dependencies from Debian 12 packages (idempotent).
# Every dependency is found by CMake's find_package; nothing is downloaded outside apt, except
# one npm package for a test: TinyUSDZ, an independent USD reader (tests/usd/, pinned by its
# package-lock.json), installed into tests/usd/node_modules.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtinyobjloader-dev libtbb-dev libembree-dev libpng-dev libsimdjson-dev
  python3-numpy python3-matplotlib python3-skimage
  pybind11-dev python3-dev python3-pytest
  python3-dask python3-distributed python3-tqdm  # the Dask engine of ringlet batch and its test
  libglfw3-dev libimgui-dev libgl-dev libepoxy-dev fonts-dejavu-core  # the studio (its UI font)
  xvfb xauth libgl1-mesa-dri xdotool  # the studio's headless tests (xdotool: real input events)
  clang-14 libclang-rt-14-dev
  blender  # the Blender add-on's tests (tests/blender/, headless Blender 3.4.1 with Cycles)
  slurm-wlm munge  # tests/slurm_test.sh: a real Slurm 22.05 (slurmctld, slurmd, munged) on loopback
  ffmpeg  # `ringlet simulate --render`'s hair.mp4 (tests/cli_simulate_test.sh)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js and npm for tests/usd (Debian's nodejs + npm, unless a Node.js with npm is there).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
else
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

usd="$(cd "$(dirname "$0")/.." && pwd)/tests/usd"
if [ -f "$usd/node_modules/tinyusdz/tinyusdz.wasm" ]; then
  echo "setup: TinyUSDZ already installed in tests/usd/node_modules"
else
  echo "setup: installing TinyUSDZ (npm) into tests/usd/node_modules"
  # Not fatal: without it only tests/usd is skipped (ctest says so), the rest builds and runs.
  (cd "$usd" && npm ci --no-audit --no-fund --loglevel=error) ||
    echo "setup: WARNING: npm could not install TinyUSDZ; the test usd_tinyusdz will be skipped" >&2
fi
