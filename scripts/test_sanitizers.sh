#!/usr/bin/env bash
# Builds the native test suites with AddressSanitizer + UndefinedBehaviorSanitizer into
# build-asan/ and runs them; any report fails the run (halt_on_error, no recovery).
# Usage: scripts/test_sanitizers.sh [extra ctest arguments, e.g. -R robustness]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake_bin=/usr/bin/cmake
[ -x "$cmake_bin" ] || cmake_bin=cmake
build_dir=${PURL_ASAN_BUILD_DIR:-build-asan}
jobs=${PURL_JOBS:-$(nproc)}
start=$(date +%s)
# RelWithDebInfo: -O2 keeps the render tests' sample counts affordable; -g gives readable reports.
"$cmake_bin" -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPURL_SANITIZE=ON \
  -DPURL_BUILD_PYTHON=OFF -DPURL_BUILD_TESTS=ON -DPURL_BUILD_BENCHMARKS=OFF -DPURL_TEST_TIMEOUT=3000 >/dev/null
"$cmake_bin" --build "$build_dir" -j "$jobs"
built=$(date +%s)
# detect_leaks: LeakSanitizer too. The Embree and TBB libraries are not instrumented, which
# ASan handles; ODR checks stay on.
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
(cd "$build_dir" && ctest --output-on-failure -j "$jobs" "$@") || status=1
end=$(date +%s)
echo "test_sanitizers: build $((built - start)) s, tests $((end - built)) s, status $status" >&2
exit $status
