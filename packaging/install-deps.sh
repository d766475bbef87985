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
  libssl-dev
  # studio
  qt6-base-dev libqt6opengl6-dev qt6-svg-dev qt6-charts-dev qt6-qpa-plugins libvtk9-dev libopenmpi-dev
  libgl1-mesa-dri libglx-mesa0 libegl-mesa0
  # offscreen renderer (widgets/render/): Xlib to check the display (Xvfb, below, is started when DISPLAY is unset)
  libx11-dev
  # the Python module (python/, docs/python.md), its tests and the Dask runner
  pybind11-dev python3-dev python3-numpy python3-distributed python3-pytest
  # tests, benchmarks, packaging
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth dpkg-dev file
  # the studio's PDF report read back as text and pictures (pdftotext, pdftoppm)
  poppler-utils
  # glTF validation in the tests (Khronos gltf-validator from npm)
  nodejs
  # engine tests: Babylon.js and three.js in headless Chromium (tests/engines)
  chromium
  # batches on Dask (python/lodforge/dask_batch.py) and its tests
  python3-distributed python3-numpy python3-pytest
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

# Debian's nodejs comes without npm; some node builds bundle it (and then conflict with Debian's npm).
command -v npm >/dev/null 2>&1 || missing+=(npm)

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
else
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  # unsafe-io: dpkg skips its fsync per file, which is most of an install's time on a fresh machine.
  $SUDO apt-get install -y -qq --no-install-recommends -o DPkg::Options::=--force-unsafe-io "${missing[@]}"
fi

# The Khronos glTF validator (npm) for the export tests, pinned in tests/gltf_validator/package-lock.json.
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ ! -f "$root/tests/gltf_validator/node_modules/gltf-validator/package.json" ]; then
  echo "install-deps: installing gltf-validator (npm)"
  (cd "$root/tests/gltf_validator" && npm ci --no-audit --no-fund --loglevel=error)
fi

# The engine tests' packages (npm): puppeteer-core, Babylon.js with its loaders, three.js, pinned in
# tests/engines/package-lock.json (tests/engines/engines_test.mjs).
if [ ! -f "$root/tests/engines/node_modules/puppeteer-core/package.json" ] ||
   [ ! -f "$root/tests/engines/node_modules/babylonjs-loaders/package.json" ] ||
   [ ! -f "$root/tests/engines/node_modules/three/package.json" ]; then
  echo "install-deps: installing puppeteer-core, babylonjs, three (npm, engine tests)"
  (cd "$root/tests/engines" && npm ci --no-audit --no-fund --loglevel=error)
fi

# The fidelity benchmark's comparators (npm): gltfpack and meshoptimizer's JS simplifier, pinned in
# bench/comparators/package-lock.json (bench/fidelity_bench.mjs).
if [ ! -f "$root/bench/comparators/node_modules/gltfpack/package.json" ] ||
   [ ! -f "$root/bench/comparators/node_modules/meshoptimizer/package.json" ]; then
  echo "install-deps: installing gltfpack and meshoptimizer (npm, benchmark comparators)"
  (cd "$root/bench/comparators" && npm ci --no-audit --no-fund --loglevel=error)
fi
