#!/usr/bin/env bash
# Runs the Blender test suites: tests/blender headless on both supported Blenders,
# tests/blender_window in a real window, and the render-farm suite (tests/farm, docs/farm.md):
#   3.4     Debian's Blender 3.4.1, the legacy zip (purlcore bundled) as a legacy add-on
#   bpy     the bpy module from PyPI (4.5 LTS by default) in a venv, the extension zip (purlcore
#           wheel inside) installed as an extension
#   window  Blender 3.4 with a window under Xvfb, the legacy zip: import, Rendered viewport,
#           a material edit, the Render and Material tabs, F12 (screenshots and times in
#           test-artifacts/window/)
#   farm    the Flamenco job type under Node, then its commands and the Open Job Description
#           template run end to end with Debian's Blender and the legacy zip
# Both zips come from scripts/build_addon.sh, run first (its CMake build folder is kept, so a
# second run only repacks).
# Installs what is missing (apt: blender, python3-pytest, python3-numpy, python3-venv, nodejs; pip: bpy,
# flip-evaluator for the OSL-vs-native image test, openjd-cli for the farm suite).
#
#   scripts/test_blender.sh [3.4|bpy|window|farm|all] [-- pytest args]
# Environment:
#   PURL_BPY_VENV      venv for the bpy module          (default /opt/purl-bpy)
#   PURL_BPY_VERSION   bpy version spec                 (default 4.5.*; 5.0.* also works)
#   PURL_SKIP_NATIVE=1 build nothing and load addon/ from the tree: tests that need purlcore
#                      skip (unless PURL_BUILD_DIR names a build folder holding it)
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SUITE=all
case "${1:-}" in 3.4|bpy|window|farm|all) SUITE="$1"; shift ;; esac
if [ "${1:-}" = "--" ]; then shift; fi
VENV="${PURL_BPY_VENV:-/opt/purl-bpy}"
BPY_VERSION="${PURL_BPY_VERSION:-4.5.*}"

log() { echo "== test_blender.sh: $*"; }
apt_install() {
    log "apt-get install $*"
    if [ -z "${PURL_APT_UPDATED:-}" ]; then apt-get update -qq; PURL_APT_UPDATED=1; fi
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
}

ensure_blender() {
    local missing=()
    command -v blender >/dev/null || missing+=(blender)
    dpkg -s python3-pytest >/dev/null 2>&1 || missing+=(python3-pytest)
    dpkg -s python3-numpy >/dev/null 2>&1 || missing+=(python3-numpy)
    [ ${#missing[@]} -eq 0 ] || apt_install "${missing[@]}"
}

ensure_bpy() {
    if "$VENV/bin/python" -c 'import bpy, pytest, numpy, flip_evaluator' >/dev/null 2>&1; then return; fi
    [ -x "$VENV/bin/python" ] || /usr/bin/python3 -m venv "$VENV" 2>/dev/null ||
        { apt_install python3-venv; /usr/bin/python3 -m venv "$VENV"; }
    log "pip install bpy==$BPY_VERSION pytest numpy flip-evaluator into $VENV (about 400 MB)"
    "$VENV/bin/pip" install -q "bpy==$BPY_VERSION" pytest numpy flip-evaluator
}

ensure_xvfb() {
    command -v xvfb-run >/dev/null || apt_install xvfb
}

ensure_native() {
    [ -z "${PURL_SKIP_NATIVE:-}" ] || return 0
    export PURL_REQUIRE_NATIVE=1  # tests that need purlcore fail instead of skipping
    log "building purlcore and the add-on zips (scripts/build_addon.sh)"
    local start=$SECONDS
    "$REPO/scripts/build_addon.sh" >/dev/null
    log "build took $((SECONDS - start)) s"
}

package_zip() {  # package_zip legacy|extension: the zip to test, empty when skipping native
    [ -z "${PURL_SKIP_NATIVE:-}" ] || return 0
    ls "$REPO"/dist/purl-*-"$1".zip | head -1
}

run_34() {
    ensure_blender
    local zip; zip="$(package_zip legacy)"
    log "Blender $(blender -v 2>/dev/null | head -1 | cut -d' ' -f2), ${zip:-addon/ from the tree}"
    local start=$SECONDS
    PURL_LEGACY_ZIP="$zip" blender -b --factory-startup --python-exit-code 1 \
        --python "$REPO/tests/blender/run_tests.py" -- "$@"
    log "Blender 3.4 suite took $((SECONDS - start)) s"
}

run_bpy() {
    ensure_bpy
    local zip; zip="$(package_zip extension)"
    log "bpy $("$VENV/bin/python" -c 'import bpy; print(bpy.app.version_string)' 2>/dev/null), ${zip:-addon/ from the tree}"
    local start=$SECONDS
    PURL_EXTENSION_ZIP="$zip" "$VENV/bin/python" "$REPO/tests/blender/run_tests.py" "$@"
    log "bpy suite took $((SECONDS - start)) s"
}

ensure_farm_tools() {
    command -v node >/dev/null || apt_install nodejs
    python3 -c 'import openjd.cli' >/dev/null 2>&1 || {
        log "pip install openjd-cli"
        python3 -m pip install -q --disable-pip-version-check openjd-cli
    }
}

run_farm() {
    ensure_blender
    ensure_farm_tools
    local zip; zip="$(package_zip legacy)"
    local start=$SECONDS
    node --test "$REPO/tests/farm/test_flamenco_job.js"
    if [ -z "$zip" ] && [ -z "${PURL_BUILD_DIR:-}" ]; then
        log "farm: no add-on zip and no PURL_BUILD_DIR, so no purlcore for the workers: renders skipped"
    else
        PURL_LEGACY_ZIP="$zip" python3 -m pytest -q -p no:cacheprovider "$REPO/tests/farm" "$@"
    fi
    log "farm suite took $((SECONDS - start)) s"
}

run_window() {
    ensure_blender
    ensure_xvfb
    local zip; zip="$(package_zip legacy)"
    log "Blender $(blender -v 2>/dev/null | head -1 | cut -d' ' -f2) in a window (Xvfb), ${zip:-addon/ from the tree}"
    local start=$SECONDS
    # Debian's Python runs pytest here: Blender finds its own Python home from the python3 on PATH.
    PURL_LEGACY_ZIP="$zip" /usr/bin/python3 -m pytest -q -s -p no:cacheprovider "$REPO/tests/blender_window" "$@"
    log "window suite took $((SECONDS - start)) s (screenshots and times in test-artifacts/window/)"
}

ensure_native
case "$SUITE" in
    3.4) run_34 "$@" ;;
    bpy) run_bpy "$@" ;;
    window) run_window "$@" ;;
    farm) run_farm "$@" ;;
    all) run_34 "$@"; run_bpy "$@"; run_window "$@"; run_farm "$@" ;;
    *) echo "usage: $0 [3.4|bpy|window|farm|all] [-- pytest args]" >&2; exit 2 ;;
esac
