#!/usr/bin/env bash
# Installs every Debian 12 package LodForge needs to build, test, benchmark and package.
# Idempotent: packages already present are skipped, so a second run costs only a dpkg query.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config clang libclang-rt-14-dev
  # core dependencies
  libeigen3-dev libtinygltf-dev libtinyobjloader-dev libstb-dev nlohmann-json3-dev
  libcli11-dev libtbb-dev libopenmesh-dev libmeshoptimizer-dev libnanoflann-dev
  # studio
  qt6-base-dev libqt6opengl6-dev qt6-svg-dev qt6-charts-dev qt6-qpa-plugins libvtk9-dev libopenmpi-dev
  libgl1-mesa-dri libglx-mesa0 libegl-mesa0
  # tests, benchmarks, packaging
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth dpkg-dev file
  # glTF validation in the tests (Khronos gltf-validator from npm)
  nodejs npm
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
