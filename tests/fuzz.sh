#!/usr/bin/env bash
# Fresh fuzzing with libFuzzer (clang; the sanitizer build of
# tests/sanitize.sh): each target named (default: all) runs for SECONDS
# (default 1800) from a copy of its seed corpus in fuzz/corpus/TARGET, one
# target per core. New inputs go to build-sanitize/fuzz/corpus/TARGET;
# crashes, leaks, timeouts and out-of-memory inputs to
# build-sanitize/fuzz/findings/TARGET, and a summary to
# build-sanitize/fuzz/TARGET.log. Add inputs worth keeping to fuzz/corpus.
#   bash tests/fuzz.sh [SECONDS [TARGET ...]]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-1800}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(field_description scene_loader mesh_file point_set saved_fit image)
command -v clang++ >/dev/null || { echo "fuzz.sh: needs clang (Debian: apt-get install clang)" >&2; exit 2; }
bash tests/sanitize.sh --build
# intercept_tls_get_addr=0: see tests/sanitize.sh.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/sanitizer_suppressions.txt:print_suppressions=0
run() {
  local target=$1 work=build-sanitize/fuzz
  mkdir -p "$work/corpus/$target" "$work/findings/$target"
  cp -n fuzz/corpus/"$target"/* "$work/corpus/$target/" 2>/dev/null || true
  # 30 s per input, 4 GB: slower or larger inputs are findings too.
  build-sanitize/fuzz/"${target}"_fuzzer "$work/corpus/$target" -max_total_time="$seconds" -timeout=30 \
    -rss_limit_mb=4096 -max_len=16384 -print_final_stats=1 -artifact_prefix="$work/findings/$target/" \
    >"$work/$target.log" 2>&1 || true
  echo "$target: $(grep -E '^stat::number_of_executed_units' "$work/$target.log" | awk '{print $2}') executions," \
       "$(ls "$work/findings/$target" | wc -l) findings"
}
running=0
for target in "${targets[@]}"; do
  run "$target" &
  running=$((running + 1))
  if ((running >= 2)); then wait -n; running=$((running - 1)); fi
done
wait
