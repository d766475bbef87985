#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build of the core, the `lodforge` CLI and their tests,
# then the tests under it (docs/bad-input.md).
#   packaging/sanitize.sh [--ci] [cmake arguments...]
# Default: build-asan/, every test labelled core or cli (LODFORGE_SANITIZE_LABELS picks others).
# --ci: build-asan-ci/, only the reader tests (tests/io and tests/core: PLY, OBJ, glTF, hostile input,
#   the own formats' byte container), meant for CI; not in packaging/test.sh yet, because the
#   instrumented core alone takes longer than CI's budget allows (docs/bad-input.md).
# Excluded: the studio and widgets (Qt and VTK are not instrumented, and their GUI tests need an X server
# whose libraries report leaks of their own), the VTK renderer, the Python module (an instrumented
# extension needs the ASan runtime preloaded into python3), the benchmarks, and the fuzzers (built with
# clang and their own sanitizers, tests/fuzz/).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ci=0
if [ "${1:-}" = "--ci" ]; then ci=1; shift; fi
dir="${LODFORGE_SANITIZE_DIR:-$root/build-asan$([ $ci = 1 ] && echo -ci)}"
# -O1: ASan's recommendation (readable stacks, a fraction of -O2's compile time); -g1: file and line in
# reports without full debug information.
sanitize="-O1 -g1 -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=None -DLODFORGE_BUILD_STUDIO=OFF -DLODFORGE_BUILD_RENDER=OFF \
  -DLODFORGE_PYTHON=OFF -DLODFORGE_BUILD_BENCH=OFF -DLODFORGE_BUILD_FUZZ=OFF \
  -DCMAKE_CXX_FLAGS="$sanitize" -DCMAKE_C_FLAGS="$sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  "$@" >/dev/null
# Leaks are failures (LeakSanitizer, part of ASan); a UBSan report ends the test (an error, not a warning).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
if [ $ci = 1 ]; then
  tests=(core_tests io_tests ply_tests binary_io_tests)
  cmake --build "$dir" --parallel "$(nproc)" --target "${tests[@]}"
  # Run directly: ctest would also list the suite's other tests, which this stage does not build.
  for t in "${tests[@]}"; do
    (cd "$dir" && "bin/$t" --gtest_brief=1) || { echo "sanitize.sh: $t failed under ASan+UBSan" >&2; exit 1; }
  done
else
  cmake --build "$dir" --parallel "$(nproc)"
  cd "$dir"
  ctest --output-on-failure --parallel "$(nproc)" -L "${LODFORGE_SANITIZE_LABELS:-core|cli}" --timeout 1800
fi
