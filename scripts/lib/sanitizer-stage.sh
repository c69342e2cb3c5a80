#!/usr/bin/env bash
# Run by scripts/test.sh in the background (not meant to be run on its own): builds the host suites in
# build-sanitize/ (configured by test.sh: clang -O0 -g1, ASan + UBSan, -Werror) and runs them under the
# sanitizers. Prints each step's wall time; exits non-zero at the first failure, saying which step.
# Usage: scripts/lib/sanitizer-stage.sh JOBS
set -uo pipefail
cd "$(dirname "$0")/../.."
jobs=$1
t=$SECONDS
if ! cmake --build build-sanitize -j"$jobs"; then
  echo "== the ASan + UBSan build FAILED"
  exit 1
fi
echo "== ASan + UBSan build: $((SECONDS - t)) s"
t=$SECONDS
if ! ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --test-dir build-sanitize --output-on-failure -j"$jobs" -LE "consumer|fuzz"; then
  echo "== the host suites FAILED under ASan + UBSan"
  exit 2
fi
echo "== ASan + UBSan ctest: $((SECONDS - t)) s"
