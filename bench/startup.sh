#!/usr/bin/env bash
# Start-up cost of the isotrace executable: wall time and peak resident
# memory of `isotrace --version` and of a 64x48, 1-spp render of
# scenes/primitives.json (EXR and PNG preview), medians of 21 runs, and the
# number of shared libraries the executable maps. Several binaries (an
# older build and this one) are measured interleaved in one run:
#   bash bench/startup.sh [ISOTRACE ...]
set -euo pipefail
cd "$(dirname "$0")/.."
binaries=("$@"); ((${#binaries[@]})) || binaries=(build/isotrace)
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
scene=scenes/primitives.json
declare -A seconds memory
for run in $(seq 21); do
  for bin in "${binaries[@]}"; do
    for what in version render; do
      if [ "$what" = version ]; then args=(--version)
      else args=(render "$scene" --width 64 --height 48 --spp 1 --threads 2 -q -o "$scratch/out.exr"); rm -f "$scratch"/out.*; fi
      # Wall time from bash's own `time` (fork, exec and run; no helper
      # process inside the timed span: an earlier `date`/`time(1)`/`tail`
      # harness added about 20 ms), peak memory from a separate time(1) run.
      TIMEFORMAT=%3R
      elapsed=$( { time "$bin" "${args[@]}" >/dev/null 2>&1; } 2>&1 )
      seconds[$bin,$what]+="$elapsed "
      [ "$what" = render ] && rm -f "$scratch"/out.*
      kb=$(/usr/bin/time -f "%M" "$bin" "${args[@]}" 2>&1 >/dev/null | tail -1)
      memory[$bin,$what]+="$kb "
    done
  done
done
median() { tr ' ' '\n' | grep . | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
printf '%-40s %9s %14s %12s %14s %10s\n' binary "libraries" "--version s" "--version MB" "small render s" "render MB"
for bin in "${binaries[@]}"; do
  printf '%-40s %9d %14s %12.1f %14s %10.1f\n' "$bin" "$(ldd "$bin" | wc -l)" \
    "$(echo "${seconds[$bin,version]}" | median)" "$(echo "${memory[$bin,version]}" | median | awk '{ print $1 / 1024 }')" \
    "$(echo "${seconds[$bin,render]}" | median)" "$(echo "${memory[$bin,render]}" | median | awk '{ print $1 / 1024 }')"
done
