#!/usr/bin/env bash
# isotrace against POV-Ray 3.7 (Debian: apt-get install povray) on the same
# scenes, 640x480, one ray per pixel, 2 threads: whole-process wall time and
# the render phase (isotrace's "wrote ... in", POV-Ray's "Trace Time"),
# medians of interleaved runs. Each scene is a pair in bench/peers/:
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
now() { date +%s%N; }
printf '%-10s %12s %12s %12s %12s %9s %9s\n' scene "isotrace s" "render s" "POV-Ray s" "trace s" whole render
for scene in bench/peers/*_whitted.json; do
  name=$(basename "$scene" _whitted.json)
  declare -A t=()
  for run in $(seq "$runs"); do
    start=$(now)
    line=$("$isotrace" render "$scene" --threads 2 --no-preview -o "$scratch/$name.exr" 2>&1 | grep '^wrote')
    end=$(now)
    t[iso]+="$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", (b - a) / 1e9 }') "
    t[isoRender]+="$(sed -E 's/.* in ([0-9.]+)s$/\1/' <<<"$line") "
    start=$(now)
    trace=$(cd "$scratch" && povray +I"$OLDPWD/bench/peers/$name.pov" +O"$scratch/$name.png" +W640 +H480 -A +WT2 -D -V 2>&1 |
            grep 'Trace Time' | sed -E 's/.*\(([0-9.]+) seconds\).*/\1/')
    end=$(now)
    t[pov]+="$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f", (b - a) / 1e9 }') "
    t[povTrace]+="$trace "
  done
  iso=$(median <<<"${t[iso]}"); isoRender=$(median <<<"${t[isoRender]}")
  pov=$(median <<<"${t[pov]}"); povTrace=$(median <<<"${t[povTrace]}")
  printf '%-10s %12s %12s %12s %12s %8.1fx %8.1fx\n' "$name" "$iso" "$isoRender" "$pov" "$povTrace" \
    "$(awk -v a="$pov" -v b="$iso" 'BEGIN { print a / b }')" "$(awk -v a="$povTrace" -v b="$isoRender" 'BEGIN { print a / b }')"
  unset t
done
