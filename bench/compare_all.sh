#!/usr/bin/env bash
# Every speed figure of the peers comparison in one run, as ratios:
#   1. against POV-Ray 3.7 on the three small scenes (bench/compare_povray.sh);
#   2. implicit against its own polygonized mesh (render phase, --as mesh) on
#      the showcase and the tangle;
#   3. the 1,001-blob cluster: whole process, cell building, steps and kernel
#      evaluations per ray (Segment Tracing's reference code is not run here:
#      its figures, from the issue, are printed beside ours);
#   4. start-up (bench/startup.sh);
#   5. the variational hand against its triangles (bench/variational_render);
#   6. marching cubes and adaptive polygonization (bench/polygonize_throughput).
#   bash bench/compare_all.sh [RUNS]       (needs a Release build in build/)
# Run it on an otherwise idle machine: the figures are medians of
# interleaved runs, but two cores shared with other work still drift.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
isotrace=build/isotrace
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
median() { tr ' ' '\n' | grep . | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
now() { date +%s%N; }
seconds() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.4f", (b - a) / 1e9 }'; }
renderSeconds() { sed -n 's/^wrote .* in \([0-9.]*\)s$/\1/p'; }

echo "== 1. POV-Ray 3.7, 640x480, 1 ray per pixel, Whitted, 2 threads (whole process, render phase; ratio = POV-Ray / isotrace)"
if command -v povray >/dev/null; then bash bench/compare_povray.sh "$runs" "$isotrace"
else echo "   povray is not installed (apt-get install povray): skipped"; fi

echo
echo "== 2. implicit against its polygonized mesh: render phase, 320x180, 16 spp, path, 2 threads (ratio = implicit / mesh; target <= 1.0 showcase, <= 1.5 tangle)"
for scene in scenes/showcase.json scenes/tangle.json; do
  implicit=""; mesh=""
  for run in $(seq "$runs"); do
    for as in implicit mesh; do
      s=$("$isotrace" render "$scene" --as "$as" --width 320 --height 180 --spp 16 --threads 2 --no-preview \
          -o "$scratch/as.exr" 2>&1 | renderSeconds)
      if [ "$as" = implicit ]; then implicit+="$s "; else mesh+="$s "; fi
    done
  done
  i=$(median <<<"$implicit"); m=$(median <<<"$mesh")
  printf '   %-22s implicit %.3f s  mesh %.3f s  ratio %.2fx\n' "$scene" "$i" "$m" "$(awk -v a="$i" -v b="$m" 'BEGIN { print a / b }')"
done

echo
echo "== 3. 1,001 blobs (bench/scenes/blob_cluster.json, 500x500 primary rays, 2 threads)"
whole=""; render=""
for run in $(seq "$runs"); do
  start=$(now)
  r=$("$isotrace" render bench/scenes/blob_cluster.json --threads 2 --no-preview -o "$scratch/blobs.exr" 2>&1 | renderSeconds)
  end=$(now)
  whole+="$(seconds "$start" "$end") "; render+="$r "
done
printf '   isotrace whole process %.3f s, render %.3f s (medians of %d)\n' "$(median <<<"$whole")" "$(median <<<"$render")" "$runs"
build/bench/implicit_throughput 2>/dev/null | grep 'blob_cluster (' | sed 's/^/   /'
echo "   Segment Tracing reference code (Galin et al. 2020), as the issue measured it: 0.60 s whole, 5.43 steps,"
echo "   6.3 kernel evaluations and 23 bound queries per ray (not run here)"

echo
echo "== 4. start-up"
bash bench/startup.sh "$isotrace" | sed 's/^/   /'

echo
echo "== 5. variational fit of hand.off against its triangles (640x480, 16 spp)"
build/bench/variational_render 2>/dev/null | sed 's/^/   /'

echo
echo "== 6. polygonization at 256^3"
build/bench/polygonize_throughput 2>/dev/null | sed 's/^/   /'
