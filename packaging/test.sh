#!/usr/bin/env bash
# Set-up command 2: install what is missing, build, and run the whole test suite (ctest).
# GUI tests start their own X server (xvfb-run), so no display is needed.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/packaging/install-deps.sh"
"$root/packaging/build.sh"
cd "$root/build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 600
