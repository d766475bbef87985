#!/usr/bin/env bash
# The long fuzz run of issue 32 (docs/bad-input.md): each reader's libFuzzer target, one after the other,
# from its seed corpus, until RUNS executions or SECONDS seconds, whichever comes first. The seeds and
# what earlier runs found are first merged (-merge=1) into a minimal corpus (OUT/TARGET/corpus) that keeps
# their coverage. Prints one line per target (executions, exec/s, corpus inputs and bytes, finding or
# not) and exits 1 when any target found something; the crashing inputs are kept in OUT/TARGET/ as
# libFuzzer writes them (crash-*, leak-*, oom-*, timeout-*). Inputs are at most 32 KB (the largest seed).
#   packaging/fuzz-long.sh [--runs N] [--seconds S] [--out DIR] [--no-build] [TARGET...]
# Targets: ply gltf obj lfo mco lodstrips lodstrips_file preset landmarks lfmorph lfmstrips (default: all).
# Needs a configured build/ (the fuzz targets and the seed corpora are built here; --no-build uses
# them as they are, e.g. while another build runs in build/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build"
runs=1000000
seconds=0
out="$build/fuzz-long"
targets=()
build_first=1
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --no-build) build_first=0; shift ;;
    -h|--help) sed -n '2,12p' "${BASH_SOURCE[0]}"; exit 0 ;;
    -*) echo "fuzz-long.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(ply gltf obj lfo mco lodstrips lodstrips_file preset landmarks lfmorph lfmstrips)

# The seed corpora are written by ctest fixtures (they need the CLI and the shared meshes).
if [ $build_first = 1 ]; then
  cmake --build "$build" --target lodforge ply_fuzz_seeds $(for t in "${targets[@]}"; do echo "${t}_fuzz"; done) >/dev/null
  (cd "$build" && ctest -R fuzz_seed_corpus --output-on-failure >/dev/null) ||
    { echo "fuzz-long.sh: writing the seed corpora failed (ctest -R fuzz_seed_corpus)" >&2; exit 1; }
fi

seeds_of() {
  case "$1" in
    ply) echo "$build/tests/fuzz/ply_corpus/seeds" ;;
    lodstrips|lodstrips_file) echo "$build/tests/fuzz/reader_corpus/lodstrips" ;;  # runtime and file reader
    *) echo "$build/tests/fuzz/reader_corpus/$1" ;;
  esac
}

found=0
printf '%-16s %10s %8s %7s %14s  %s\n' target executions seconds exec/s corpus result
for t in "${targets[@]}"; do
  bin="$build/bin/${t}_fuzz"
  [ -x "$bin" ] || { echo "fuzz-long.sh: no $bin (clang++ missing?)" >&2; exit 1; }
  seeds="$(seeds_of "$t")"
  [ -d "$seeds" ] || { echo "fuzz-long.sh: no seed corpus $seeds for $t" >&2; exit 1; }
  dir="$out/$t"
  mkdir -p "$dir/corpus"
  rm -rf "$dir/merged"
  mkdir "$dir/merged"
  log="$dir/fuzz.log"
  # -rss_limit_mb=1024 makes any input that needs more than 1 GB a finding, -timeout=20 any input that
  # takes more than 20 s (a hang).
  limits=(-max_len=32768 -rss_limit_mb=1024 -timeout=20 -artifact_prefix="$dir/")
  rc=0
  (cd "$dir" && "$bin" -merge=1 "${limits[@]}" merged corpus "$seeds") >"$dir/merge.log" 2>&1 || rc=$?
  if [ "$rc" -eq 0 ]; then
    rm -rf "$dir/corpus"
    mv "$dir/merged" "$dir/corpus"
    start=$(date +%s)
    # The corpus directory receives what this run finds.
    (cd "$dir" && "$bin" corpus -runs="$runs" -max_total_time="$seconds" "${limits[@]}" -print_final_stats=1) \
      >"$log" 2>&1 || rc=$?
    seconds_taken=$(( $(date +%s) - start ))
  else
    log="$dir/merge.log" seconds_taken=0
  fi
  stat_of() { grep -o "stat::$1: *[0-9]*" "$log" | grep -o '[0-9]*$' || echo '?'; }
  corpus="$(find "$dir/corpus" -type f | wc -l) / $(( $(du -sb "$dir/corpus" | cut -f1) / 1024 )) KB"
  result="no finding"
  if [ "$rc" -ne 0 ]; then
    found=1
    result="FINDING (exit $rc): $(grep -m1 -o 'SUMMARY: .*\|ERROR: libFuzzer: .*' "$log" || echo "see $log")"
  fi
  printf '%-16s %10s %8s %7s %14s  %s\n' "$t" "$(stat_of number_of_executed_units)" "$seconds_taken" \
    "$(stat_of average_exec_per_sec)" "$corpus" "$result"
done
exit "$found"
