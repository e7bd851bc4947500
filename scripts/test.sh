#!/usr/bin/env bash
# Sets up, builds and runs every test suite: native (ctest, once per Embree ISA), Python (pytest), when
# scripts/test_blender.sh is present the add-on inside Blender, then the native suites under
# ASan + UBSan and a short fuzz run of the file readers (docs/robustness.md).
# PURL_SANITIZERS=0 / PURL_FUZZ=0 skip the last two (each is a build of its own; timings in
# docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
status=0
# The native suites once per Embree instruction set this CPU has (PURL_EMBREE_ISA), best
# first (Embree's own choice): images must not depend on the machine. The first pass runs every
# suite; the others the suites that trace rays through Embree (render, robustness, scene,
# reference, and the multi-scale image tests). docs/robustness.md has the times.
flags=" $(grep -m1 '^flags' /proc/cpuinfo | cut -d: -f2) "
has() { for f in "$@"; do [[ "$flags" == *" $f "* ]] || return 1; done; }
isas=""
has avx512f avx512dq avx512cd avx512bw avx512vl && isas="$isas avx512"
has avx2 fma bmi2 && isas="$isas avx2"
has sse4_2 && isas="$isas sse4.2"
[ -n "$isas" ] || isas="sse2"
first=1
for isa in $isas; do
  start=$(date +%s)
  if [ $first = 1 ]; then
    (cd build && PURL_EMBREE_ISA=$isa ctest --output-on-failure -j 2) || status=1
  else
    (cd build && PURL_EMBREE_ISA=$isa ctest --output-on-failure -j 2 -L '^(render|robustness|scene|reference)$') ||
      status=1
    (cd build && PURL_EMBREE_ISA=$isa ctest --output-on-failure -j 2 -R '^MultiscaleImages[.]') || status=1
  fi
  echo "test.sh: native suites with Embree ISA $isa: $(( $(date +%s) - start )) s" >&2
  first=0
done
PYTHONPATH="$PWD/build" python3 -m pytest -q tests/python || status=1
if [ -f scripts/test_blender.sh ]; then
  bash scripts/test_blender.sh || status=1
fi
# Benchmark pipeline end to end on one tiny scene, with one Cycles render when the bpy venv made
# by test_blender.sh is there (asserts that it runs, nothing about time).
python3 bench/run.py --quick --build-dir build || status=1
if [ "${PURL_SANITIZERS:-1}" = 1 ]; then
  bash scripts/test_sanitizers.sh || status=1
fi
if [ "${PURL_FUZZ:-1}" = 1 ]; then
  bash scripts/fuzz.sh 20 || status=1
fi
exit $status
