#!/usr/bin/env bash
# Builds the Blender add-on in both forms, into dist/:
#   dist/purl-<version>-extension.zip  Blender 4.2+ extension: add-on, manifest, purlcore wheel
#   dist/purl-<version>-legacy.zip     Blender 3.x add-on: folder purl/ with purlcore*.so inside
#   dist/wheels/purlcore-<version>-cp311-cp311-linux_x86_64.whl
# The wheel is built by scikit-build-core (pyproject.toml) from the top-level CMakeLists.txt with
# Debian's -dev packages. Environment: PYTHON (a CPython 3.11, default python3),
# PURL_WHEEL_BUILD_DIR (CMake build folder kept between runs, default /tmp/purl-wheel-build).
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DIST="$REPO/dist"
PYTHON="${PYTHON:-python3}"
BUILD_DIR="${PURL_WHEEL_BUILD_DIR:-/tmp/purl-wheel-build}"

fail() { echo "build_addon.sh: $*" >&2; exit 1; }

"$PYTHON" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' ||
    fail "$PYTHON is not Python 3.11; Blender 3.4-5.0 need a cp311 module (set PYTHON=...)"

# One version everywhere: CMake project, extension manifest, bl_info.
version="$(sed -n 's/^project(purl VERSION \([0-9.]*\).*/\1/p' "$REPO/CMakeLists.txt")"
manifest_version="$(sed -n 's/^version = "\(.*\)"/\1/p' "$REPO/blender_manifest.toml")"
bl_info_version="$(sed -n 's/^ *"version": (\([0-9]*\), *\([0-9]*\), *\([0-9]*\)).*/\1.\2.\3/p' "$REPO/addon/__init__.py")"
[ -n "$version" ] || fail "no 'project(purl VERSION x.y.z)' in CMakeLists.txt"
[ "$version" = "$manifest_version" ] || fail "blender_manifest.toml version $manifest_version != CMake $version"
[ "$version" = "$bl_info_version" ] || fail "bl_info version $bl_info_version != CMake $version"

# --- the purlcore wheel ---
mkdir -p "$DIST/wheels"
rm -f "$DIST"/wheels/purlcore-*.whl
isolation="--no-build-isolation"
"$PYTHON" -c 'import scikit_build_core' 2>/dev/null || isolation=""  # then pip fetches it from PyPI
echo "== building the purlcore wheel (build folder $BUILD_DIR)"
CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-2}" \
    "$PYTHON" -m pip wheel "$REPO" --no-deps $isolation --wheel-dir "$DIST/wheels" \
    --config-settings "build-dir=$BUILD_DIR"
wheel="$(ls "$DIST"/wheels/purlcore-"$version"-cp311-cp311-linux_x86_64.whl 2>/dev/null || true)"
[ -n "$wheel" ] || fail "pip made no purlcore-$version-cp311-cp311-linux_x86_64.whl in $DIST/wheels"
"$PYTHON" - "$wheel" <<'PY' || fail "the wheel holds no purlcore module: CMakeLists.txt needs install(TARGETS purlcore ... COMPONENT purlcore)"
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
sys.exit(0 if any(n.startswith("purlcore") and n.endswith(".so") for n in names) else 1)
PY

# --- stage and zip both forms ---
stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT
copy_addon() {  # the add-on's Python files and the shipped presets, nothing built or cached
    "$PYTHON" -c 'import shutil, sys; shutil.copytree(sys.argv[1], sys.argv[2],
        ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "*.so"))' "$REPO/addon" "$1"
    mkdir -p "$1/presets"
    cp "$REPO"/presets/*.json "$1/presets/" 2>/dev/null || true
}
zip_folder() {  # zip_folder <folder> <zip>: the folder's entries at the zip's root
    rm -f "$2"
    (cd "$1" && "$PYTHON" -m zipfile -c "$2" $(ls -A))
}

ext="$stage/extension"
copy_addon "$ext"
mkdir -p "$ext/wheels"
cp "$wheel" "$ext/wheels/"
sed "s|^wheels = .*|wheels = [\"./wheels/$(basename "$wheel")\"]|" "$REPO/blender_manifest.toml" > "$ext/blender_manifest.toml"
zip_folder "$ext" "$DIST/purl-$version-extension.zip"

legacy="$stage/legacy/purl"
copy_addon "$legacy"
"$PYTHON" - "$wheel" "$legacy" <<'PY'
import sys, zipfile
wheel = zipfile.ZipFile(sys.argv[1])
for name in wheel.namelist():
    if name.startswith("purlcore") and name.endswith(".so"):
        wheel.extract(name, sys.argv[2])
PY
zip_folder "$stage/legacy" "$DIST/purl-$version-legacy.zip"

echo "== built"
ls -l "$DIST"/purl-"$version"-*.zip "$wheel"
