#!/usr/bin/env bash
# Set-up command 1: install what is missing, build, and run the main job — the studio on the bundled
# Spot sample, or (no display) the headless run: CLI report, conversion and a rendered thumbnail.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/packaging/install-deps.sh"
"$root/packaging/build.sh"
sample="$root/resources/samples/spot/spot_triangulated.obj"
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec "$root/build/bin/lodforge-studio" "$sample"
fi
echo "No display: headless run on $sample"
"$root/build/bin/lodforge" info "$sample"
"$root/build/bin/lodforge" convert "$sample" "$root/build/spot.ply"
xvfb-run -a -s "-screen 0 1280x800x24" \
  "$root/build/bin/lodforge-studio" "$sample" --screenshot "$root/build/spot-studio.png"
echo "Wrote $root/build/spot.ply and the studio's rendering $root/build/spot-studio.png"
