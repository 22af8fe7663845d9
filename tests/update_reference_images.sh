#!/usr/bin/env bash
# Regenerates reference images on purpose (the test suite never does):
#   bash tests/update_reference_images.sh             # every scene
#   bash tests/update_reference_images.sh showcase    # one scene
# Renders with the settings in reference_images/render-settings.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
isotrace=${ISOTRACE:-build/isotrace}
read -r -a settings < reference_images/render-settings.txt
if (($#)); then names=("$@"); else names=(); for f in scenes/*.json; do names+=("$(basename "$f" .json)"); done; fi
for name in "${names[@]}"; do
  echo "reference_images/$name.exr" >&2
  "$isotrace" render "scenes/$name.json" "${settings[@]}" --threads 2 --no-preview --quiet -o "reference_images/$name.exr"
done
