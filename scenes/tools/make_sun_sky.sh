#!/usr/bin/env bash
# Makes scenes/environments/sun_sky.exr, the sun-and-sky map of
# bench/scenes/sun_sky.json, with OpenImageIO's oiiotool (Debian
# openimageio-tools): a latitude-longitude map 1024x512 whose top 8 rows
# (within 2.8 degrees of the zenith) are a sun cap of radiance 2,000, over a
# blue sky down to the horizon and a grey ground below it. The map depends
# on the polar angle alone, so any renderer's azimuth convention sees the
# same sky.
set -euo pipefail
cd "$(dirname "$0")/.."
oiiotool --pattern constant:color=0.25,0.45,0.9 1024x512 3 \
  --fill:color=2000,2000,2000 1024x8+0+0 \
  --fill:color=0.3,0.3,0.3 1024x256+0+256 \
  -d half --compression zip -o environments/sun_sky.exr
