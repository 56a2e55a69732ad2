#!/usr/bin/env bash
# Installs ringlet's build and test dependencies from Debian 12 packages (idempotent).
# Every dependency is found by CMake's find_package; nothing is downloaded outside apt.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtinyobjloader-dev libtbb-dev libembree-dev libpng-dev libsimdjson-dev
  python3-numpy python3-matplotlib python3-skimage
  pybind11-dev python3-dev python3-pytest
  libglfw3-dev libimgui-dev libgl-dev libepoxy-dev fonts-dejavu-core  # the studio (its UI font)
  xvfb xauth libgl1-mesa-dri xdotool  # the studio's headless tests (xdotool: real input events)
  clang-14 libclang-rt-14-dev
  blender  # the Blender add-on's tests (tests/blender/, headless Blender 3.4.1 with Cycles)
  slurm-wlm munge  # tests/slurm_test.sh: a real Slurm 22.05 (slurmctld, slurmd, munged) on loopback
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
