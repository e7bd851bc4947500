#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) into build-fuzz/ and runs each for N
# seconds, niced, from tests/fuzz/corpus plus what earlier runs found (build-fuzz/corpus).
# Findings (crash-*, timeout-*, oom-*) go to build-fuzz/findings/<run>/<target>/; any finding fails.
# Usage: scripts/fuzz.sh [seconds per target, default 20] [target ...]
#   targets: fuzz_bcc fuzz_scene_json fuzz_preset (default: all)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_bcc fuzz_scene_json fuzz_preset)

# clang and its libFuzzer runtime from Debian, as setup.sh installs the rest.
if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  echo "fuzz: installing clang and libclang-rt" >&2
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  rt=$(apt-cache search --names-only '^libclang-rt-[0-9]+-dev$' | sort -V | tail -1 | cut -d' ' -f1)
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq clang "$rt" >/dev/null
fi

cmake_bin=/usr/bin/cmake
[ -x "$cmake_bin" ] || cmake_bin=cmake
build_dir=${PURL_FUZZ_BUILD_DIR:-build-fuzz}
jobs=${PURL_JOBS:-$(nproc)}
start=$(date +%s)
CC=clang CXX=clang++ "$cmake_bin" -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DPURL_SANITIZE=ON -DPURL_BUILD_FUZZERS=ON -DPURL_BUILD_TESTS=OFF -DPURL_BUILD_PYTHON=OFF >/dev/null
"$cmake_bin" --build "$build_dir" -j "$jobs" --target "${targets[@]}"
echo "fuzz: build $(( $(date +%s) - start )) s" >&2

status=0
run_id=$(date +%Y%m%d-%H%M%S)
for target in "${targets[@]}"; do
  name=${target#fuzz_}
  corpus="$build_dir/corpus/$name"
  findings="$build_dir/findings/$run_id/$name"
  mkdir -p "$corpus" "$findings"
  log="$build_dir/$target.log"
  # New inputs go to the first folder (build-fuzz/corpus); the committed seeds stay as they are.
  # -timeout: one input may take 10 s; -rss_limit_mb: and 2 GB, or it is a finding too.
  set +e
  nice -n 10 "$build_dir/tests/fuzz/$target" "$corpus" "tests/fuzz/corpus/$name" \
    -dict="tests/fuzz/$name.dict" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$findings/" -print_final_stats=1 >"$log" 2>&1
  rc=$?
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  found=$(find "$findings" -type f | wc -l)
  echo "fuzz: $target ${seconds} s: ${execs:-?} executions, cov ${cov:-?}, ft ${ft:-?}, findings $found (exit $rc)"
  if [ "$rc" -ne 0 ] || [ "$found" -ne 0 ]; then
    status=1
    grep -E 'ERROR|SUMMARY|runtime error|uncaught|accepted|Test unit written' "$log" | head -20 >&2 || true
  fi
done
exit $status
