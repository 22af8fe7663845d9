#!/usr/bin/env bash
# Scale (#64): scenes of many primitives at constant density (centres
# scattered through a cube whose volume grows with their number, the camera
# framing the cube), 500x500, one ray per pixel, Whitted, 2 threads. For
# each: the render's own time (the "wrote ... in" line), the whole
# process, its peak memory and that per primitive, and the marching steps
# per pixel (the steps AOV's mean, with oiiotool). Medians of 3 runs.
#   bash bench/scale.sh [ISOTRACE] [--quick]   (--quick: stop at 10^5)
# The light families are bench/many_lights (a C++ benchmark).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/isotrace
quick=0
for arg in "$@"; do
  case "$arg" in
    --quick) quick=1 ;;
    *) bin=$arg ;;
  esac
done
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT

# scene FILE FAMILY COUNT: writes a scene of COUNT primitives of FAMILY.
scene() {
  python3 - "$@" <<'EOF'
import json, math, random, sys
path, family, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
# About one sphere of radius 0.06 per 0.125 cubic units.
half = 0.5 * (count * 0.125) ** (1 / 3)
region = [[-half] * 3, [half] * 3]
def scatter(**extra):
    s = {"type": "scatter", "count": count, "seed": 1, "region": region,
         "shape": {"type": "sphere", "radius": 0.15}, "scale": [0.7, 1.3]}
    s.update(extra)
    return s
if family == "union":
    field = scatter()
elif family == "smooth_union":
    field = scatter(operation="smooth_union", radius=0.1)
elif family == "difference":
    field = {"type": "difference", "of": [{"type": "box", "size": [2 * half] * 3}, scatter()]}
elif family == "blobs":
    rng = random.Random(1)
    field = {"type": "blobby", "kernel": "poly6", "threshold": 0.3, "blobs": [
        {"center": [rng.uniform(-half, half) for _ in range(3)], "radius": 0.45} for _ in range(count)]}
distance = 3.2 * half + 1
scene = {
    "camera": {"from": [0.55 * distance, 0.45 * distance, distance], "to": [0, 0, 0], "fov": 40},
    "film": {"width": 500, "height": 500, "spp": 1},
    "integrator": {"type": "whitted", "max_depth": 2},
    "materials": {"clay": {"type": "diffuse", "albedo": [0.7, 0.6, 0.5]}},
    "fields": {"many": field},
    "objects": [{"field": "many", "material": "clay"}],
    "lights": [{"type": "directional", "direction": [-1, -2, -1.5], "irradiance": [3, 3, 3]},
               {"type": "environment", "radiance": [0.3, 0.3, 0.35]}]}
with open(path, "w") as f:
    json.dump(scene, f)
EOF
}

median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

run() {  # run FAMILY COUNT
  local family=$1 count=$2 file="$scratch/$1_$2.json" renders="" wholes="" peaks=""
  scene "$file" "$family" "$count"
  for round in 1 2 3; do
    rm -f "$scratch"/out.*
    local log="$scratch/log"
    /usr/bin/time -f "%e %M" -o "$scratch/time" "$bin" render "$file" --threads 2 --no-preview -o "$scratch/out.exr" >"$log" 2>&1
    renders+="$(grep -o 'in [0-9.]*s' "$log" | tail -1 | tr -dc '0-9.') "
    read -r wall kb <"$scratch/time"
    wholes+="$wall "
    peaks+="$kb "
  done
  "$bin" render "$file" --threads 2 --no-preview --aov steps -q -o "$scratch/steps.exr" >/dev/null 2>&1
  local steps
  steps=$(oiiotool "$scratch/steps.exr" --ch steps --printstats 2>/dev/null | awk '/Stats Avg/ {print $3; exit}') || steps="?"
  local render whole peak
  render=$(echo "$renders" | median); whole=$(echo "$wholes" | median); peak=$(echo "$peaks" | median)
  printf '| %s | %s | %s s | %s s | %d MB | %d B | %s |\n' "$family" "$count" "$render" "$whole" $((peak / 1024)) \
    $((peak * 1024 / count)) "${steps:-?}"
}

echo "| family | primitives | render | whole process | peak memory | per primitive | steps per pixel |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
counts=(1000 10000 100000 1000000)
((quick)) && counts=(1000 10000 100000)
for n in "${counts[@]}"; do run union "$n"; done
for family in smooth_union difference; do
  for n in 1000 100000; do run "$family" "$n"; done
done
blob_counts=(1000 100000 1000000)
((quick)) && blob_counts=(1000 100000)
for n in "${blob_counts[@]}"; do run blobs "$n"; done
