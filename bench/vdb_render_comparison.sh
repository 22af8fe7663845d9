#!/usr/bin/env bash
# isotrace against OpenVDB's own ray tracer (vdb_render, LevelSetRayIntersector)
# on two level sets: the tangle written by `isotrace voxelize`, and hand.off
# turned into a level set by OpenVDB's vdb_tool. Same camera, one ray per
# pixel, 2 threads, each renderer's whole process (median of RUNS). Prints
# the times, their ratio, and how many pixels one renderer hits and the
# other misses; writes the images side by side into OUT. isotrace renders
# with a directional light (a shadow ray per hit), and again without lights
# (camera rays only, as vdb_render's shaders cast).
#
#   bash bench/vdb_render_comparison.sh [OUT] [RESOLUTION] [RUNS] [IMAGE_SIZE]
#
# Also times the export against polygonizing the same field at the same
# resolution. Needs libopenvdb-tools (vdb_render, vdb_tool).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/isotrace-vdb-bench}
resolution=${2:-256}
runs=${3:-5}
size=${4:-512}
isotrace=$PWD/build/isotrace
data=$PWD/../shared/data
mkdir -p "$out"
for tool in vdb_render vdb_tool oiiotool; do
  command -v $tool >/dev/null || { echo "needs $tool (apt-get install libopenvdb-tools openimageio-tools)"; exit 2; }
done

calc() { awk "BEGIN {printf \"%.6f\", $1}"; }
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
seconds() {  # the whole process's wall time
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null 2>&1
  end=$(date +%s.%N)
  calc "$end - $start"
}

# ---- the level sets ---------------------------------------------------------
cp scenes/tangle.json "$out/tangle_scene.json"
echo "export of the tangle at resolution $resolution (median of $runs):"
export_times=() polygonize_times=()
for i in $(seq "$runs"); do
  export_times+=("$(seconds "$isotrace" voxelize "$out/tangle_scene.json" --field tangle -o "$out/tangle.vdb" \
    --resolution "$resolution" --threads 2)")
  polygonize_times+=("$(seconds "$isotrace" polygonize "$out/tangle_scene.json" --field tangle -o "$out/tangle.ply" \
    --resolution "$resolution" --threads 2)")
done
voxelize_s=$(printf '%s\n' "${export_times[@]}" | median)
polygonize_s=$(printf '%s\n' "${polygonize_times[@]}" | median)
printf '  voxelize %.3f s, polygonize %.3f s (whole processes), ratio %.2f\n' "$voxelize_s" "$polygonize_s" \
  "$(calc "$voxelize_s / $polygonize_s")"

# hand.off as OBJ for vdb_tool, which reads no OFF.
awk 'NR==1 {next} NR==2 {nv=$1; next} nv > 0 {print "v", $1, $2, $3; nv--; next}
     NF >= 4 {printf "f"; for (i = 2; i <= $1 + 1; i++) printf " %d", $i + 1; print ""}' \
  "$data/hand.off" > "$out/hand.obj"
vdb_tool -read "$out/hand.obj" -mesh2ls dim="$resolution" width=3 -write "$out/hand.vdb" >/dev/null
vdb_print "$out/hand.vdb" | head -3

# ---- the renders ------------------------------------------------------------
# camera: from, to (world units), vertical field of view of a square image
render_pair() {
  local name=$1 vdb=$2 from=$3 to=$4 fov=$5
  cat > "$out/$name.json" <<EOF
{
  "camera": { "from": [$from], "to": [$to], "fov": $fov },
  "film": { "width": $size, "height": $size, "spp": 1 },
  "integrator": { "type": "whitted", "max_depth": 1 },
  "materials": { "clay": { "type": "diffuse", "albedo": [0.8, 0.8, 0.8] } },
  "fields": { "surface": { "type": "vdb", "file": "$(basename "$vdb")" } },
  "objects": [ { "field": "surface", "material": "clay" } ],
  "lights": [ { "type": "directional", "direction": [-0.3, -0.3, -0.4], "irradiance": [3, 3, 3] } ]
}
EOF
  # The same without lights: camera rays only, as vdb_render's shaders cast.
  sed 's/"lights": \[.*\]$/"lights": []/' "$out/$name.json" > "$out/${name}_camera_rays.json"
  local iso_times=() iso_camera_times=() vdb_times=()
  for i in $(seq "$runs"); do
    iso_times+=("$(seconds "$isotrace" render "$out/$name.json" -o "$out/${name}_isotrace.exr" --threads 2 --quiet \
      --no-preview)")
    iso_camera_times+=("$(seconds "$isotrace" render "$out/${name}_camera_rays.json" -o "$out/${name}_camera_rays.exr" \
      --threads 2 --quiet --no-preview)")
    vdb_times+=("$(seconds vdb_render "$vdb" "$out/${name}_vdb_render.exr" -res ${size}x${size} -cpus 2 -samples 1 \
      -shader diffuse -translate "$from" -lookat "$to" -up 0,1,0 -fov "$fov" -compression none)")
  done
  local iso iso_camera vdbr
  iso=$(printf '%s\n' "${iso_times[@]}" | median)
  iso_camera=$(printf '%s\n' "${iso_camera_times[@]}" | median)
  vdbr=$(printf '%s\n' "${vdb_times[@]}" | median)
  # Coverage: isotrace's depth (0 where a ray misses) against where
  # vdb_render's normal shader leaves a normal (its alpha is 1 everywhere).
  vdb_render "$vdb" "$out/${name}_vdb_normals.exr" -res ${size}x${size} -cpus 2 -samples 1 -shader normal \
    -translate "$from" -lookat "$to" -up 0,1,0 -fov "$fov" -compression none >/dev/null
  "$isotrace" render "$out/$name.json" -o "$out/${name}_depth.exr" --threads 2 --quiet --no-preview --aov depth
  oiiotool "$out/${name}_depth.exr" --ch Z --mulc 1e30 --clamp:min=0:max=1 -o "$out/${name}_iso_mask.exr"
  oiiotool "$out/${name}_vdb_normals.exr" --ch R,G,B --abs --chsum --mulc 1e30 --clamp:min=0:max=1 \
    -o "$out/${name}_vdb_mask.exr"
  local differ
  differ=$(oiiotool "$out/${name}_iso_mask.exr" "$out/${name}_vdb_mask.exr" --absdiff --printstats |
    awk '/Stats Avg:/ {print $3; exit}')
  oiiotool "$out/${name}_isotrace.exr" --ch R,G,B "$out/${name}_vdb_render.exr" --ch R,G,B --mosaic 2x1 \
    -o "$out/${name}_side_by_side.png"
  printf '%-8s isotrace %.3f s (camera rays only %.3f s), vdb_render %.3f s, vdb_render / isotrace %.2fx (%.2fx); pixels hit by one and not the other: %.4f%%\n' \
    "$name" "$iso" "$iso_camera" "$vdbr" "$(calc "$vdbr / $iso")" "$(calc "$vdbr / $iso_camera")" "$(calc "$differ * 100")"
}

echo "renders at ${size}x${size}, 1 ray per pixel, 2 threads, whole process (median of $runs):"
render_pair tangle "$out/tangle.vdb" "4.5,4.0,6.5" "0,0,0" 40
read -r cx cy cz r < <(awk 'NR==2 {nv=$1; next} NR > 2 && nv > 0 {x+=$1; y+=$2; z+=$3; n++; nv--;
  if (n == 1 || $1 < x0) x0=$1; if (n == 1 || $1 > x1) x1=$1; if (n == 1 || $2 < y0) y0=$2; if (n == 1 || $2 > y1) y1=$2;
  if (n == 1 || $3 < z0) z0=$3; if (n == 1 || $3 > z1) z1=$3}
  END {print (x0+x1)/2, (y0+y1)/2, (z0+z1)/2, sqrt((x1-x0)^2+(y1-y0)^2+(z1-z0)^2)/2}' "$data/hand.off")
render_pair hand "$out/hand.vdb" "$(calc "$cx + 1.2*$r"),$(calc "$cy + 0.9*$r"),$(calc "$cz + 2.2*$r")" \
  "$cx,$cy,$cz" 40
echo "images: $out/*_side_by_side.png (isotrace left, vdb_render right)"
