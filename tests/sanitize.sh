#!/usr/bin/env bash
# The unit tests under AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer, in ./build-sanitize (RelWithDebInfo), built
# with clang (installed when missing), so the same build also holds the
# libFuzzer targets (tests/fuzz.sh) and checks that everything compiles with
# the second compiler. The image regressions are left out: they compare
# whole renders, which take minutes under the sanitizers and test nothing
# the unit tests do not.
#   bash tests/sanitize.sh              # build and run every test
#   bash tests/sanitize.sh --build      # build only
#   bash tests/sanitize.sh --shard K/N  # build, then run every N-th test from the K-th
#                                       # (CI: each folder has tests in every shard)
set -euo pipefail
cd "$(dirname "$0")/.."
ISOTRACE_INSTALL_CLANG=1 bash .ci/setup
# Line tables only: the sanitizers' stack traces need no more, and full
# debug information made the build half again as long.
if [ ! -f build-sanitize/build.ninja ]; then
  cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
    -DISOTRACE_SANITIZE=address,undefined -DISOTRACE_FUZZ=ON -DISOTRACE_BENCH=OFF >/dev/null
fi
cmake --build build-sanitize -j2
[ "${1:-}" = "--build" ] && exit 0
shard=()
if [ "${1:-}" = "--shard" ]; then
  IFS=/ read -r k n <<< "${2:?--shard K/N}"
  shard=(-I "$((k + 1)),,$n")
fi
# intercept_tls_get_addr=0: up to LLVM 16 the runtime's __tls_get_addr
# interceptor can take a malloc'd block for a pre-2.25 glibc TLS header,
# and LeakSanitizer's tracer then dies at exit ("Tracer caught signal 11")
# in a process that leaked nothing, one run in a few hundred.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:intercept_tls_get_addr=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Leaks inside third-party libraries only (see the file); print_suppressions=0
# keeps the corpus's "no sanitizer text" check meaningful.
export LSAN_OPTIONS=suppressions=$PWD/tests/sanitizer_suppressions.txt:print_suppressions=0
# Left out: the image regressions (above), the installed-package test,
# whose consumer is built without the sanitizers and so cannot link the
# instrumented library, and the whole-program runs on emulated CPUs, with
# capped kernels, from the Debian package, on a Slurm farm and in Blender
# (the plain build runs them). (Sanitized tests run 3-10x slower: tests/CMakeLists.txt
# gives them longer timeouts.)
ctest --test-dir build-sanitize --output-on-failure -j2 -E 'SceneRegression|installed_geometry_package|OtherCpus|InstructionSetCaps|DebianPackage|SlurmFarm|Blender' "${shard[@]}"
