#!/usr/bin/env bash
# Sets up, builds and renders the demo: a generated stockinette knit swatch.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
mkdir -p out
build/purl render scenes/demo_knit.json -o out/demo.exr --png out/demo.png --stats
echo "demo: out/demo.png (sRGB) and out/demo.exr (multilayer: Combined, Depth, Normal, YarnID, PlyIndex, PlyUV): a stockinette swatch with 3-ply BYSDF yarns"
