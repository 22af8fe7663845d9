#!/usr/bin/env bash
# Fit quality as a user sees it: every model in ../shared/data (or the
# files given) fitted by both methods (defaults), measured by
# `isotrace fit --report`: time, closedness, components and genus against
# the input's, and the two-sided distance over the bounding diagonal.
#
#   bash bench/fit_quality.sh [MODEL ...]
set -euo pipefail
cd "$(dirname "$0")/.."
isotrace=$PWD/build/isotrace
models=("$@")
if ((${#models[@]} == 0)); then
  models=(../shared/data/*.off ../shared/data/*.xyz ../shared/data/*.pwn)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| model | method | fit time | closed | components | genus (fit / input) | mean distance | max distance |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for model in "${models[@]}"; do
  for method in mpu variational; do
    start=$(date +%s.%N)
    if ! "$isotrace" fit "$model" -o "$work/fit.json" --method "$method" -q > /dev/null 2> "$work/err"; then
      echo "| $(basename "$model") | $method | failed: $(head -c 120 "$work/err") | | | | | |"
      continue
    fi
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    "$isotrace" fit "$model" -o "$work/fit.json" --method "$method" -q --report > "$work/report.json" 2> /dev/null
    python3 - "$model" "$method" "$seconds" "$work/report.json" <<'PY'
import json, os, sys
model, method, seconds, path = sys.argv[1:]
r = json.load(open(path))
fit, given = r["fit"], r.get("input")
genus = f'{fit["genus"]} / {given["genus"] if given else "-"}'
d = r.get("distance", {"mean": float("nan"), "max": float("nan")})
print(f'| {os.path.basename(model)} | {method} | {float(seconds):.2f} s | {fit["closed"]} | {fit["components"]} | '
      f'{genus} | {d["mean"]:.2e} | {d["max"]:.2e} |')
PY
  done
done
