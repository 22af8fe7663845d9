#!/usr/bin/env bash
# Makes scenes/textures/tiles.png, the image texture of scenes/materials.json,
# with OpenImageIO's oiiotool (Debian openimageio-tools): 4x4 warm and cool
# tiles of 32 pixels separated by dark 2-pixel grout, 128x128, sRGB.
set -euo pipefail
cd "$(dirname "$0")/.."
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
oiiotool --pattern checker:width=32:height=32:color1=0.72,0.52,0.38:color2=0.45,0.55,0.62 128x128 3 -o "$scratch/tiles.exr"
# Grout: a 128x128 mask that is 0 on the first two rows and columns of every tile.
oiiotool --pattern fill:color=1,1,1 30x30 3 -o "$scratch/tile.exr"
oiiotool "$scratch/tile.exr" --pattern constant:color=0.12,0.12,0.12 32x32 3 --paste +2+2 -o "$scratch/cell.exr"
oiiotool "$scratch/cell.exr" --dup --dup --dup --mosaic 4x1 --dup --dup --dup --mosaic 1x4 -o "$scratch/mask.exr"
oiiotool "$scratch/tiles.exr" "$scratch/mask.exr" --mul -d uint8 --tocolorspace sRGB -o textures/tiles.png
