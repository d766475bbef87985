#!/usr/bin/env bash
# Configures and builds LodForge into build/ (binaries in build/bin). Used by start.sh and test.sh.
# LODFORGE_WERROR=ON (the default under CI=true) turns warnings into errors.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
werror="${LODFORGE_WERROR:-$([ "${CI:-}" = "true" ] && echo ON || echo OFF)}"
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLODFORGE_WERROR="$werror" "$@"
cmake --build "$root/build" --parallel "$(nproc)"
