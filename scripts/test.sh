#!/usr/bin/env bash
# Sets up, builds and runs every test suite: native (ctest), Python (pytest) and, when
# scripts/test_blender.sh is present, the add-on inside Blender.
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
exit $status
