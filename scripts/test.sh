#!/usr/bin/env bash
# Sets up, builds and runs every test suite: native (ctest), Python (pytest), when
# scripts/test_blender.sh is present the add-on inside Blender, then the native suites under
# ASan + UBSan and a short fuzz run of the file readers (docs/robustness.md).
# PURL_SANITIZERS=0 / PURL_FUZZ=0 skip the last two (each is a build of its own; timings in
# docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
status=0
(cd build && ctest --output-on-failure -j 2) || status=1
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
