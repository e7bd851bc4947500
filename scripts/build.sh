#!/usr/bin/env bash
# Configures and builds everything (library, CLI, Python module, tests) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
# Debian's CMake: the pip one on PATH may be 4.x, which rejects older package configs.
cmake_bin=/usr/bin/cmake
[ -x "$cmake_bin" ] || cmake_bin=cmake
build_dir=${PURL_BUILD_DIR:-build}
"$cmake_bin" -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DPython_EXECUTABLE="$(command -v python3)" "$@" >/dev/null
"$cmake_bin" --build "$build_dir" -j "$(nproc)"
