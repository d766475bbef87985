#!/usr/bin/env bash
# The source document's dragon experiments (000_*, appendix Tables A1-A3) with the octree builder:
# per setting (max triangles per leaf, max depth) the build time, peak memory and triangles per level;
# for the depth-8 settings, levels 1-3 against the input (Metro mean, RMS, Hausdorff) next to an edge
# collapse (`lodforge simplify`) to the same triangle count. Prints Markdown tables (docs/benchmarks.md).
#
#     bench/octree_document_tables.sh [LODFORGE] [SETTINGS]
#
# LODFORGE: the CLI (default build/bin/lodforge); SETTINGS: space-separated max,depth pairs
# (default: the document's ten, "100,5 100,8 200,5 200,8 1000,5 1000,8 2000,5 2000,8 3000,5 3000,8").
# LEVELS (environment, default "1 2 3"): the levels measured on the depth-8 settings ("" for sizes only).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lodforge="${1:-$root/build/bin/lodforge}"
settings="${2:-100,5 100,8 200,5 200,8 1000,5 1000,8 2000,5 2000,8 3000,5 3000,8}"
input="$root/../shared/data/scan-dragon/dragon_vrip.ply"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
memory=64
levels_measured="${LEVELS-1 2 3}"

field() { sed -n "s/.*\"$2\": *\([-0-9.e+]*\).*/\1/p" "$1" | head -1; }

echo "| max tris | depth | leaves | build s | M tris/s | peak RSS MB (limit $((memory + 64))) | triangles per level (1 = leaves) | level ratios |"
echo "|---|---|---|---|---|---|---|---|"
quality=""
for s in $settings; do
    max="${s%,*}" depth="${s#*,}"
    asset="$tmp/d$max-$depth.lfo"
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$lodforge" --quiet octree build "$input" -o "$asset" \
        --max-triangles "$max" --max-depth "$depth" --memory "$memory" --temp-dir "$tmp" > /dev/null
    read -r wall rss < "$tmp/time"
    "$lodforge" --quiet octree info "$asset" --json > "$tmp/info.json"
    levels="$(tr -d '\n ' < "$tmp/info.json" | sed -n 's/.*"triangles_per_level":\[\([0-9,]*\)\].*/\1/p')"
    leaves="$(tr -d '\n ' < "$tmp/info.json" | sed -n 's/.*"leaves":\([0-9]*\).*/\1/p')"
    ratios="$(echo "$levels" | awk -F, '{ for (i = 3; i <= NF; ++i) printf "%s%d %%", (i > 3 ? ", " : ""), 100 * $i / $(i - 1) }')"
    echo "| $max | $depth | $leaves | $wall | $(awk -v w="$wall" 'BEGIN { printf "%.2f", 0.871414 / w }') | $((rss / 1024)) | ${levels#*,} | $ratios |"
    [ "$depth" = 8 ] || continue
    for level in $levels_measured; do
        tris="$(echo "$levels" | cut -d, -f$((level + 1)))"
        [ -n "$tris" ] || continue
        "$lodforge" --quiet octree extract "$asset" --level "$level" -o "$tmp/level.ply" > /dev/null
        "$lodforge" --quiet compare "$input" "$tmp/level.ply" --json > "$tmp/o.json"
        "$lodforge" --quiet simplify "$input" -o "$tmp/collapse.ply" --triangles "$tris" > /dev/null
        "$lodforge" --quiet compare "$input" "$tmp/collapse.ply" --json > "$tmp/c.json"
        quality+="| $max / $depth | $level | $tris | $(field "$tmp/o.json" mean) | $(field "$tmp/o.json" rms) | $(field "$tmp/o.json" hausdorff) | $(field "$tmp/c.json" mean) | $(field "$tmp/c.json" rms) | $(field "$tmp/c.json" hausdorff) |"$'\n'
    done
done
echo
echo "| max tris / depth | level | triangles | octree mean | octree RMS | octree Hausdorff | collapse mean | collapse RMS | collapse Hausdorff |"
echo "|---|---|---|---|---|---|---|---|---|"
printf "%s" "$quality"
