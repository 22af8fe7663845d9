#!/usr/bin/env bash
# isotrace against POV-Ray 3.7 (Debian: apt-get install povray) on the same
# scenes, 640x480, one ray per pixel, 2 threads: whole-process wall time and
# the render phase (isotrace's "wrote ... in", which includes compressing
# the EXR as rows finish; POV-Ray's "Trace Time", which excludes writing its
# PNG), medians of interleaved runs. Each scene is a pair in bench/peers/:
# NAME_whitted.json and NAME.pov (same camera, box and light; POV-Ray's
# max_gradient is the field's true bound over the box).
#   bash bench/compare_povray.sh [RUNS [ISOTRACE]]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
isotrace=${2:-build/isotrace}
command -v povray >/dev/null || { echo "compare_povray.sh: needs povray (apt-get install povray)" >&2; exit 2; }
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
median() { tr ' ' '\n' | grep . | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
printf '%-10s %12s %12s %12s %12s %9s %9s\n' scene "isotrace s" "render s" "POV-Ray s" "trace s" whole render
for scene in bench/peers/*_whitted.json; do
  name=$(basename "$scene" _whitted.json)
  declare -A t=()
  for run in $(seq "$runs"); do
    # Wall time from bash's own `time` around each process alone (a
    # date/grep/pipe harness around it added 10-20 ms to every run).
    TIMEFORMAT=%3R
    t[iso]+="$( { time "$isotrace" render "$scene" --threads 2 --no-preview -o "$scratch/$name.exr" >"$scratch/log" 2>&1; } 2>&1 ) "
    line=$(grep '^wrote' "$scratch/log")
    t[isoRender]+="$(sed -E 's/.* in ([0-9.]+)s$/\1/' <<<"$line") "
    t[pov]+="$(cd "$scratch" && { time povray +I"$OLDPWD/bench/peers/$name.pov" +O"$scratch/$name.png" +W640 +H480 -A +WT2 -D -V >"$scratch/povlog" 2>&1; } 2>&1 ) "
    trace=$(grep 'Trace Time' "$scratch/povlog" | sed -E 's/.*\(([0-9.]+) seconds\).*/\1/')
    t[povTrace]+="$trace "
  done
  iso=$(median <<<"${t[iso]}"); isoRender=$(median <<<"${t[isoRender]}")
  pov=$(median <<<"${t[pov]}"); povTrace=$(median <<<"${t[povTrace]}")
  printf '%-10s %12s %12s %12s %12s %8.1fx %8.1fx\n' "$name" "$iso" "$isoRender" "$pov" "$povTrace" \
    "$(awk -v a="$pov" -v b="$iso" 'BEGIN { print a / b }')" "$(awk -v a="$povTrace" -v b="$isoRender" 'BEGIN { print a / b }')"
  unset t
done
