#!/usr/bin/env bash
# Skinned characters: one collapse level at 25 % and 10 % of the triangles, bind pose only and with the
# pose-sampled cost (--pose-samples 8), beside gltfpack (-si R -sv -se 1 -noq: without -se 1 it stops at its 1 % error default, above the
# target). For each: triangles, seconds,
# the mean surface distance in the bind pose and the mean and worst over 16 animation poses (`compare
# --poses 16`, % of the bind-pose diagonal), the ratio pose mean / bind mean, and in how many of the 16
# poses the level's mean error is at most gltfpack's. Prints a Markdown table (docs/skinning.md).
#
#     bench/skin_bench.sh [LODFORGE] [GLTFPACK]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lodforge="${1:-$root/build/bin/lodforge}"
gltfpack="${2:-$root/bench/comparators/node_modules/.bin/gltfpack}"
data="$root/../shared/data"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
poses=16

# Seconds of wall time of a command.
timed() {
    local start end
    start=$(date +%s.%N)
    "$@" >"$tmp/last.log" 2>&1
    end=$(date +%s.%N)
    echo "$end - $start" | bc
}
measure() {  # measure IN LEVEL JSON (an empty object when the level has no triangles left)
    "$lodforge" --quiet compare "$1" "$2" --poses "$poses" --samples 50000 --json >"$3" 2>/dev/null || echo '{}' >"$3"
}
pct() { jq -r "if .diagonal then $1 * 100 / .diagonal | . * 1000 | round / 1000 else \"—\" end" "$2"; }

echo "| asset | ratio | method | triangles | s | bind mean % | pose mean % | pose worst mean % | pose/bind | poses ≤ gltfpack |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for asset in skin-cesium-man/CesiumMan.glb skin-rigged-simple/RiggedSimple.glb; do
    in="$data/$asset"
    name="$(basename "$asset" .glb)"
    for ratio in 0.25 0.1; do
        t_g=$(timed "$gltfpack" -i "$in" -o "$tmp/g.glb" -si "$ratio" -sv -se 1 -noq)
        measure "$in" "$tmp/g.glb" "$tmp/g.json"
        t_b=$(timed "$lodforge" simplify "$in" -o "$tmp/b.glb" --ratio "$ratio" --placement half-edge)
        measure "$in" "$tmp/b.glb" "$tmp/b.json"
        t_p=$(timed "$lodforge" simplify "$in" -o "$tmp/p.glb" --ratio "$ratio" --pose-samples 8)
        measure "$in" "$tmp/p.glb" "$tmp/p.json"
        for m in b p g; do
            case $m in b) label="collapse, bind pose"; t=$t_b ;; p) label="collapse, 8 poses"; t=$t_p ;; g) label="gltfpack -sv"; t=$t_g ;; esac
            f="$tmp/$m.json"
            beats=$(jq -rs 'if .[0].poses and .[1].poses then [.[0].poses.frames, .[1].poses.frames] | transpose | map(select(.[0].mean <= .[1].mean)) | length else "—" end' "$f" "$tmp/g.json")
            [ "$beats" = "—" ] || beats="$beats/$poses"
            printf "| %s | %s | %s | %s | %.2f | %s | %s | %s | %s | %s |\n" "$name" "$ratio" "$label" \
                "$(jq -r '.triangles.test // 0' "$f")" "$t" "$(pct .mean "$f")" "$(pct .poses.mean_mean "$f")" \
                "$(pct .poses.worst_mean "$f")" "$(jq -r 'if .diagonal and .mean > 1e-5 * .diagonal then (.poses.mean_mean / .mean * 100 | round / 100) else "—" end' "$f")" "$beats"
        done
    done
done
