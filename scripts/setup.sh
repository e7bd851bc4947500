#!/usr/bin/env bash
# Installs what Purl needs to build and test, from Debian's packages and PyPI, skipping
# what is already there. Safe to run again.
set -euo pipefail

packages=(build-essential cmake ninja-build pkg-config
          libembree-dev libopenimageio-dev openimageio-tools libtbb-dev
          pybind11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev libcli11-dev python3-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}" >/dev/null
fi

# pyoidn: Intel Open Image Denoise 2 for --denoise (Debian 12 has no OIDN; Purl opens the
# library it installs at run time, docs/denoising.md).
python3 -m pip install -q --disable-pip-version-check numpy "pybind11>=2.12" pytest matplotlib flip-evaluator \
    "pyoidn>=2.5,<3" >/dev/null
