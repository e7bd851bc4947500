#!/usr/bin/env bash
# Sets up, builds and runs every test suite: native (ctest), Python (pytest), when
# scripts/test_blender.sh is present the add-on inside Blender, then the native suites under
# ASan + UBSan and a short fuzz run of the file readers (docs/robustness.md).
# The sanitizer and fuzz runs are opt-in (PURL_SANITIZERS=1, PURL_FUZZ=1) until they have been
# seen green and timed inside CI's budget; see docs/robustness.md.
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
if [ "${PURL_SANITIZERS:-0}" = 1 ]; then
  bash scripts/test_sanitizers.sh || status=1
fi
if [ "${PURL_FUZZ:-0}" = 1 ]; then
  bash scripts/fuzz.sh 20 || status=1
fi
exit $status
