#!/usr/bin/env bash
# `lodforge batch` over a directory of meshes (default: every shared mesh) with the default preset:
# wall time with --jobs 1 and --jobs 2 (fresh output roots), the re-run with nothing changed, and with
# DASK=1 the Dask runner on a LocalCluster of 2 workers, its packs compared byte for byte with the
# --jobs 2 packs. Prints a Markdown table (docs/benchmarks.md, "Batch").
#
#     bench/batch_bench.sh [LODFORGE] [SOURCE]
#
# LODFORGE: the CLI (default build/bin/lodforge); SOURCE: a directory or manifest (default ../shared/data).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lodforge="${1:-$root/build/bin/lodforge}"
source_dir="${2:-$root/../shared/data}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Seconds of wall time of a command (its output kept in $tmp/last.log; a failed asset is not an error here).
timed() {
    local start end
    start=$(date +%s.%N)
    "$@" >"$tmp/last.log" 2>&1 || true
    end=$(date +%s.%N)
    echo "$end - $start" | bc
}
summary() { sed -n 's/.*"\(ok\|failed\|skipped\)": \([0-9]*\).*/\1 \2/p' "$1/batch-report.json" | tr '\n' ' '; }

t1=$(timed "$lodforge" --quiet batch "$source_dir" -o "$tmp/j1" --jobs 1)
s1=$(summary "$tmp/j1")
t2=$(timed "$lodforge" --quiet batch "$source_dir" -o "$tmp/j2" --jobs 2)
s2=$(summary "$tmp/j2")
t3=$(timed "$lodforge" --quiet batch "$source_dir" -o "$tmp/j2" --jobs 2)
s3=$(summary "$tmp/j2")

echo "| run | assets (report summary) | wall s | vs --jobs 1 |"
echo "|---|---|---|---|"
echo "| --jobs 1 | $s1 | $t1 | 1.00x |"
printf '| --jobs 2 | %s | %s | %.2fx faster |\n' "$s2" "$t2" "$(echo "$t1 / $t2" | bc -l)"
printf '| re-run, nothing changed (--jobs 2) | %s | %s | %.1f %% of the --jobs 2 run |\n' "$s3" "$t3" \
    "$(echo "100 * $t3 / $t2" | bc -l)"
if [ "${DASK:-0}" = 1 ]; then
    python="${PYTHON:-/usr/bin/python3}"
    t4=$(timed "$python" "$root/python/lodforge/dask_batch.py" "$source_dir" -o "$tmp/dask" --workers 2 \
         --lodforge "$lodforge")
    s4=$(summary "$tmp/dask")
    # Every pack file of the Dask run against the batch's: identical bytes (state and report differ).
    files=0 differ=0
    while IFS= read -r f; do
        files=$((files + 1))
        cmp -s "$tmp/j2/$f" "$tmp/dask/$f" || differ=$((differ + 1))
    done < <(cd "$tmp/j2" && find . -type f ! -name 'batch-*.json' | sort)
    printf '| Dask LocalCluster, 2 workers | %s | %s | %.2fx faster; %d of %d pack files differ from --jobs 2 |\n' \
        "$s4" "$t4" "$(echo "$t1 / $t4" | bc -l)" "$differ" "$files"
fi
