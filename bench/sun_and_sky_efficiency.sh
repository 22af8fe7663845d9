#!/usr/bin/env bash
# Monte Carlo efficiency 1/(RMSE^2 * seconds) on the sun and sky
# (scenes/sun_and_sky.json: a diffuse ball on a floor under a 2,000-radiance
# sun cap at the zenith, a blue sky and a grey ground) at 256x256 and 64 spp,
# for each isotrace binary given (default: this build) and for Cycles
# (Debian's Blender 3.4, bench/cycles/sun_and_sky.py), in one run:
#   bash bench/sun_and_sky_efficiency.sh [ISOTRACE ...]
# Each renderer renders 5 seeds, interleaved, against its own converged
# render (4,096 spp isotrace, 2,048 Cycles: their noise adds 1.6% and 3% to
# the 64-spp squared errors); seconds are each renderer's
# render call (isotrace's whole process, Cycles' bpy render call: both
# include loading the map and building their structures), medians of the
# five. Prints each renderer's efficiency, the ratio to Cycles, and the
# converged means (the renderers should agree to 0.5%).
set -euo pipefail
cd "$(dirname "$0")/.."
binaries=("$@"); ((${#binaries[@]})) || binaries=(build/isotrace)
command -v blender >/dev/null || { echo "blender is not installed (apt-get install blender)"; exit 1; }
scratch=$(mktemp -d); trap 'rm -rf "$scratch"' EXIT
scene=scenes/sun_and_sky.json sky=scenes/environments/sun_sky.exr
cycles() { # OUT SPP SEED -> seconds
  blender -b --factory-startup -noaudio -P bench/cycles/sun_and_sky.py -- "$1" "$2" "$3" "$PWD/$sky" 2>&1 |
    sed -n 's/^cycles_seconds \(.*\)/\1/p'
}
isotrace() { # BINARY OUT SPP SEED -> seconds
  local start end
  start=$(date +%s.%N)
  "$1" render "$scene" --spp "$3" --seed "$4" --threads 2 -q --no-preview -o "$2"
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.4f\n", b - a }'
}
rmse() { build/isotrace compare "$1" "$2" --metric rmse --fail 1e30 --json | sed -n 's/.*"rmse": \(.*\),/\1/p'; }
mean() { oiiotool "$1" --printstats | sed -n 's/.*Stats Avg: \([^ ]*\) \([^ ]*\) \([^ ]*\).*/\1 \2 \3/p' | awk '{ print ($1 + $2 + $3) / 3 }'; }

names=(cycles); for b in "${!binaries[@]}"; do names+=("isotrace$b"); done
cycles "$scratch/cycles-ref.exr" 2048 99 >/dev/null
for b in "${!binaries[@]}"; do isotrace "${binaries[$b]}" "$scratch/isotrace$b-ref.exr" 4096 99 >/dev/null; done
declare -A times mse
for seed in 1 2 3 4 5; do
  times[cycles]+=" $(cycles "$scratch/cycles-$seed.exr" 64 "$seed")"
  for b in "${!binaries[@]}"; do
    times[isotrace$b]+=" $(isotrace "${binaries[$b]}" "$scratch/isotrace$b-$seed.exr" 64 "$seed")"
  done
done
for name in "${names[@]}"; do
  m=0
  for seed in 1 2 3 4 5; do
    r=$(rmse "$scratch/$name-$seed.exr" "$scratch/$name-ref.exr")
    m=$(awk -v a="$m" -v r="$r" 'BEGIN { print a + r * r / 5 }')
  done
  mse[$name]=$m
  median=$(printf '%s\n' ${times[$name]} | sort -g | sed -n 3p)
  times[$name]=$median
done
cyclesEfficiency=$(awk -v m="${mse[cycles]}" -v t="${times[cycles]}" 'BEGIN { print 1 / (m * t) }')
cyclesMean=$(mean "$scratch/cycles-ref.exr")
for name in "${names[@]}"; do
  label=$name
  [[ $name == isotrace* ]] && label="${binaries[${name#isotrace}]}"
  refMean=$(mean "$scratch/$name-ref.exr")
  awk -v n="$label" -v t="${times[$name]}" -v m="${mse[$name]}" -v c="$cyclesEfficiency" -v mean="$refMean" -v cm="$cyclesMean" \
    'BEGIN { e = 1 / (m * t); printf "%-28s %.3f s  RMSE %.4f  efficiency %8.3f  x Cycles %.2f  converged mean %.5f (%+.2f%% vs Cycles)\n", n, t, sqrt(m), e, e / c, mean, 100 * (mean / cm - 1) }'
done
