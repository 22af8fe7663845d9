#!/usr/bin/env bash
# Time per sample by material: the same scene (an implicit tangle and blob
# over a floor, environment and quad light; bench/scenes/material_cost.json)
# with its subject material diffuse, smooth glass, rough glass, rough metal
# and rough plastic, rendered in interleaved rounds so that machine noise
# falls on all alike. Reports the median render seconds (the renderer's own
# timing of the render phase) per sample and the ratio to diffuse.
#   bash bench/material_cost.sh [ISOTRACE] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/isotrace}
rounds=${2:-5}
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
names=(diffuse glass rough_glass rough_metal rough_plastic)
materials=('{ "type": "diffuse", "albedo": [0.8, 0.8, 0.8] }'
           '{ "type": "dielectric", "ior": 1.5 }'
           '{ "type": "dielectric", "ior": 1.5, "roughness": 0.3 }'
           '{ "type": "conductor", "metal": "gold", "roughness": 0.3 }'
           '{ "type": "plastic", "albedo": [0.6, 0.2, 0.1], "roughness": 0.3 }')
for i in "${!names[@]}"; do
  sed "s|\"subject\": {[^}]*}|\"subject\": ${materials[$i]}|" bench/scenes/material_cost.json > "$scratch/${names[$i]}.json"
done
spp=32
declare -A times
for ((round = 0; round < rounds; ++round)); do
  for name in "${names[@]}"; do
    out="$scratch/$name.exr"
    "$bin" render "$scratch/$name.json" --spp "$spp" --threads 2 -q --no-preview -o "$out"
    times[$name]+="$(oiiotool --info -v "$out" | sed -n 's/.*isotrace:render_seconds: "\(.*\)"/\1/p') "
  done
done
median() { printf '%s\n' $1 | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
base=$(median "${times[diffuse]}")
for name in "${names[@]}"; do
  m=$(median "${times[$name]}")
  awk -v n="$name" -v m="$m" -v b="$base" -v s="$spp" \
    'BEGIN { printf "%-14s render %.3f s  %.2f ms per sample-frame  %.2fx diffuse\n", n, m, 1000 * m / s, m / b }'
done
