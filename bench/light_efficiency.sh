#!/usr/bin/env bash
# Monte Carlo efficiency 1/(RMSE^2 * seconds) of 64-spp renders against a
# converged render of the same scene, for each isotrace binary given (the
# default: this build), so that two versions are measured in one run:
#   bash bench/light_efficiency.sh [ISOTRACE ...]
# Scenes: a sphere on a floor under a small quad light
# (bench/scenes/sphere_quad.json), scenes/showcase.json and
# scenes/environment.json (lit by a sky map with a small sun), at 160x90.
# Each binary renders each scene 5 times with different seeds, against its
# own converged render; the figure uses the median render seconds (the
# renderer's own timing of the render phase) and the mean squared error
# over the five.
set -euo pipefail
cd "$(dirname "$0")/.."
binaries=("$@"); ((${#binaries[@]})) || binaries=(build/isotrace)
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
size=(--width 160 --height 90)
for scene in bench/scenes/sphere_quad.json scenes/showcase.json scenes/environment.json; do
  name=$(basename "$scene" .json)
  for b in "${!binaries[@]}"; do
    bin=${binaries[$b]}
    # The converged image of this binary at 8,192 spp: a version that finds
    # more light (a point light seen in a mirror) converges elsewhere, and
    # the figure measures noise, not that difference.
    ref="$scratch/$name-ref-$b.exr"
    "$bin" render "$scene" "${size[@]}" --spp 8192 --seed 99 --threads 2 -q --no-preview -o "$ref"
    times=(); mse=0; mseFirst=0
    for seed in 1 2 3 4 5; do
      out="$scratch/$name-$seed.exr"
      "$bin" render "$scene" "${size[@]}" --spp 64 --seed "$seed" --threads 2 -q --no-preview -o "$out"
      times+=("$(oiiotool --info -v "$out" | sed -n 's/.*isotrace:render_seconds: "\(.*\)"/\1/p')")
      rmse=$(build/isotrace compare "$out" "$ref" --metric rmse --fail 1e30 --json | sed -n 's/.*"rmse": \(.*\),/\1/p')
      mse=$(awk -v a="$mse" -v r="$rmse" 'BEGIN { print a + r * r / 5 }')
      rmse=$(build/isotrace compare "$out" "$scratch/$name-ref-0.exr" --metric rmse --fail 1e30 --json | sed -n 's/.*"rmse": \(.*\),/\1/p')
      mseFirst=$(awk -v a="$mseFirst" -v r="$rmse" 'BEGIN { print a + r * r / 5 }')
    done
    median=$(printf '%s\n' "${times[@]}" | sort -g | sed -n 3p)
    # Against its own converged render (noise alone), and against the first
    # binary's (noise and any bias, when the first is the newer and right one).
    awk -v n="$name" -v b="$bin" -v t="$median" -v m="$mse" -v f="$mseFirst" \
      'BEGIN { printf "%-12s %-40s render %.3f s  RMSE^2 %.4g  efficiency %.4g  (against the first binary: RMSE^2 %.4g, efficiency %.4g)\n", n, b, t, m, 1 / (m * t), f, 1 / (f * t) }'
  done
done
