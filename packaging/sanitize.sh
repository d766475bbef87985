#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build of the core, the `lodforge` CLI and their tests
# (build-asan/, no studio, benchmarks or fuzzers), then the core unit tests and the CLI tests under it.
# Extra arguments go to cmake; LODFORGE_SANITIZE_LABELS picks other ctest labels (default "core|cli").
# Not part of the default test run: the instrumented build alone takes far longer than the suite on
# two cores (docs/bad-input.md).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="${LODFORGE_SANITIZE_DIR:-$root/build-asan}"
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLODFORGE_BUILD_STUDIO=OFF \
  -DLODFORGE_BUILD_BENCH=OFF -DLODFORGE_BUILD_FUZZ=OFF -DCMAKE_CXX_FLAGS="$sanitize" -DCMAKE_C_FLAGS="$sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" "$@"
cmake --build "$dir" --parallel "$(nproc)"
cd "$dir"
# Leaks count as failures; a UBSan report stops the test (it is an error, not a warning).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --output-on-failure --parallel "$(nproc)" -L "${LODFORGE_SANITIZE_LABELS:-core|cli}" --timeout 1800
