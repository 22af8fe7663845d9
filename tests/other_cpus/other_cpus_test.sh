#!/usr/bin/env bash
# The binary runs where it was not built: small renders of the showcase, the
# variational figures and an MPU scan (tests/other_cpus/kitten_scan.json)
# under qemu-user emulating a Haswell
# (AVX2 and FMA, no AVX-512) and a Nehalem (SSE4.2 only), each compared with
# the native render of the same seed against the native render's own Monte
# Carlo noise (`compare --metric noise`, limit 3: the regression suite's
# tolerance, derived in tests/renderer/scene_regression_test.cpp). Each
# emulated render must also report the instruction set it ran (the EXR's
# isotrace:instruction_set). Skipped, with the reason, without qemu-x86_64:
# .ci/setup installs it when ISOTRACE_INSTALL_QEMU=1.
# With --caps, the same scenes natively with the kernels capped at SSE2 and
# at AVX2 (ISOTRACE_MAX_ISA) against the widest this CPU has: no emulator
# needed, so it always runs.
#   bash tests/other_cpus/other_cpus_test.sh [--caps] build/isotrace
set -euo pipefail
mode=qemu
if [ "${1:-}" = "--caps" ]; then mode=caps; shift; fi
isotrace=$(realpath "${1:?usage: other_cpus_test.sh [--caps] ISOTRACE}")
root=$(cd "$(dirname "$0")/../.." && pwd)
if [ "$mode" = qemu ] && ! command -v qemu-x86_64 > /dev/null; then
  echo "other_cpus_test: SKIPPED: qemu-x86_64 is not installed (apt-get install qemu-user)"
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Fits are made once, natively, and read back from the cache by the
# emulated runs: emulation is slow, and the renders are what is compared.
export ISOTRACE_CACHE_DIR="$work/cache"
settings=(--width 48 --height 36 --spp 8 --threads 2 --no-preview --quiet)
failed=0
# Scenes whose loading is light: emulation runs some 30-50x slower.
for file in scenes/showcase.json scenes/variational_figures.json tests/other_cpus/kitten_scan.json; do
  scene=$(basename "$file" .json)
  "$isotrace" render "$root/$file" "${settings[@]}" --seed 1 -o "$work/$scene.native.exr"
  "$isotrace" render "$root/$file" "${settings[@]}" --seed 2 -o "$work/$scene.native2.exr"
  if [ "$mode" = qemu ]; then runs=(Haswell:avx2 Nehalem:sse2); else runs=(cap:avx2 cap:sse2); fi
  for cpu in "${runs[@]}"; do
    model=${cpu%%:*} expected=${cpu##*:}
    out="$work/$scene.$model.$expected.exr"
    start=$(date +%s)
    if [ "$mode" = qemu ]; then
      # TCG names the host features it does not emulate on every start.
      run=(qemu-x86_64 -cpu "$model" "$isotrace")
    else
      run=(env ISOTRACE_MAX_ISA="$expected" "$isotrace")
    fi
    if ! "${run[@]}" render "$root/$file" "${settings[@]}" --seed 1 -o "$out" \
        2> >(grep -v "TCG doesn't support requested feature" >&2); then
      echo "other_cpus_test: FAILED: $scene on $model ($expected) exited non-zero" >&2
      failed=1
      continue
    fi
    seconds=$(($(date +%s) - start))
    if ! grep -aq "isotrace:instruction_set.*$expected" "$out"; then
      echo "other_cpus_test: FAILED: $scene under -cpu $model did not run the $expected kernels" >&2
      failed=1
    fi
    if score=$("$isotrace" compare "$out" "$work/$scene.native.exr" --metric noise --noise "$work/$scene.native2.exr"); then
      echo "other_cpus_test: $scene on $model ($expected kernels, ${seconds} s): $score"
    else
      echo "other_cpus_test: FAILED: $scene on $model differs from the native render by more than noise: $score" >&2
      failed=1
    fi
  done
done
if ((failed)); then exit 1; fi
echo "other_cpus_test: PASSED"
