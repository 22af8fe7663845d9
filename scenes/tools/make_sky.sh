#!/usr/bin/env bash
# Makes scenes/environments/sky.exr, the small latitude-longitude sky of
# scenes/environment.json, with OpenImageIO's oiiotool (Debian
# openimageio-tools): a blue-to-white sky over a dark ground, and a sun of
# 4x3 texels at 60 degrees elevation, 67.5 degrees right of straight ahead.
set -euo pipefail
cd "$(dirname "$0")/.."
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
oiiotool --pattern fill:top=0.35,0.55,1.1:bottom=1.2,1.15,1.05 128x32 3 -o "$scratch/up.exr"
oiiotool --pattern fill:top=0.25,0.2,0.15:bottom=0.08,0.06,0.05 128x32 3 -o "$scratch/down.exr"
oiiotool "$scratch/up.exr" "$scratch/down.exr" --mosaic 1x2 -o "$scratch/sky.exr"
oiiotool --pattern fill:color=400,370,320 4x3 3 "$scratch/sky.exr" --paste +86+9 -d half --compression zip \
  -o environments/sky.exr
