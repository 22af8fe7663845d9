#!/usr/bin/env bash
# Whole-process wall time of user-level tasks, for one or more isotrace
# binaries run interleaved (an older build against this one): medians of
# ROUNDS rounds, each round running every task with every binary in turn.
#   bash bench/whole_process.sh [--rounds N] ISOTRACE [ISOTRACE ...]
# Tasks: the showcase (640x360, 16 spp), the tangle (512x512, 16 spp), the
# 1,001-blob cluster (500x500, 1 ray per pixel, Whitted), the MPU scans scene
# (640x300, 16 spp, fits read from a warm cache), a variational fit of
# hand.off, and an adaptive polygonization of the tangle. 2 threads each
# (the fit uses all cores: run on a 2-core machine).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=5
if [ "${1:-}" = "--rounds" ]; then rounds=$2; shift 2; fi
binaries=("$@"); ((${#binaries[@]})) || binaries=(build/isotrace)
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
export ISOTRACE_CACHE_DIR=$scratch/cache
tasks=(showcase tangle blobs scans fit polygonize)
run() {
  local bin=$1 task=$2
  case $task in
    showcase) "$bin" render scenes/showcase.json --spp 16 --threads 2 -q --no-preview -o "$scratch/o.exr" ;;
    tangle) "$bin" render scenes/tangle.json --spp 16 --threads 2 -q --no-preview -o "$scratch/o.exr" ;;
    blobs) "$bin" render bench/scenes/blob_cluster.json --threads 2 -q --no-preview -o "$scratch/o.exr" ;;
    scans) "$bin" render scenes/scans.json --spp 16 --threads 2 -q --no-preview -o "$scratch/o.exr" ;;
    fit) "$bin" fit scenes/meshes/hand.off -q -o "$scratch/hand.fit.json" ;;
    polygonize) "$bin" polygonize scenes/tangle.json --field tangle --method adaptive --threads 2 -o "$scratch/t.ply" ;;
  esac >/dev/null 2>&1
}
# Warm the fit cache (both binaries read the same cache format).
for bin in "${binaries[@]}"; do run "$bin" scans; done
declare -A times
TIMEFORMAT=%3R
for round in $(seq "$rounds"); do
  for task in "${tasks[@]}"; do
    for bin in "${binaries[@]}"; do
      t=$( { time run "$bin" "$task"; } 2>&1 )
      times[$bin,$task]+="$t "
    done
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
printf '%-12s' task; for bin in "${binaries[@]}"; do printf '%24s' "$bin"; done
((${#binaries[@]} == 2)) && printf '%10s' ratio
echo
for task in "${tasks[@]}"; do
  printf '%-12s' "$task"
  values=()
  for bin in "${binaries[@]}"; do
    m=$(median <<< "${times[$bin,$task]}")
    values+=("$m")
    printf '%22.3f s' "$m"
  done
  ((${#binaries[@]} == 2)) && printf '%9.3fx' "$(awk -v a="${values[1]}" -v b="${values[0]}" 'BEGIN { print a / b }')"
  echo
done
echo "(medians of $rounds interleaved rounds; ratio = second binary / first)"
