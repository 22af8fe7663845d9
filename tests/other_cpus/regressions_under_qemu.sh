#!/usr/bin/env bash
# The scene regressions (tests/renderer/scene_regression_test.cpp) with the
# renders made under qemu-user on another CPU: each scene at the reference
# settings under `qemu-x86_64 -cpu MODEL`, scored against its reference with
# the noise of a native second-seed render, limit 3. Too slow for the suite
# (emulation runs 30-50x slower; the fitted scenes take many minutes): run by
# hand, for example before changing the suite's tolerance.
#   bash tests/other_cpus/regressions_under_qemu.sh [MODEL [SCENE ...]]   (default Haswell, every scene)
set -euo pipefail
cd "$(dirname "$0")/../.."
model=${1:-Haswell}; shift || true
isotrace=$(realpath build/isotrace)
command -v qemu-x86_64 > /dev/null || { echo "needs qemu-x86_64 (apt-get install qemu-user)" >&2; exit 2; }
read -r -a settings < reference_images/render-settings.txt
names=("$@")
if ((${#names[@]} == 0)); then for f in scenes/*.json; do names+=("$(basename "$f" .json)"); done; fi
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
export ISOTRACE_CACHE_DIR=$work/cache
failed=0
for name in "${names[@]}"; do
  second=("${settings[@]}")
  for i in "${!second[@]}"; do [ "${second[$i]}" = --seed ] && second[$((i + 1))]=2; done
  "$isotrace" render "scenes/$name.json" "${second[@]}" --threads 2 --no-preview --quiet -o "$work/$name.2.exr"
  start=$(date +%s)
  qemu-x86_64 -cpu "$model" "$isotrace" render "scenes/$name.json" "${settings[@]}" --threads 2 --no-preview --quiet \
    -o "$work/$name.exr" 2> >(grep -v "TCG doesn't support" >&2)
  if score=$("$isotrace" compare "$work/$name.exr" "reference_images/$name.exr" --metric noise --noise "$work/$name.2.exr"); then
    verdict=passed
  else
    verdict=FAILED; failed=1
  fi
  echo "$name on $model: $verdict, $(grep -o 'noise score [^ ]*' <<< "$score"), $(($(date +%s) - start)) s"
done
exit $failed
