#!/usr/bin/env bash
# The unit tests under AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer, in ./build-sanitize (RelWithDebInfo). Built
# with clang when it is installed, so the same build also holds the
# libFuzzer targets (tests/fuzz.sh); with g++ otherwise. The image
# regressions are left out: they compare whole renders, which take minutes
# under the sanitizers and test nothing the unit tests do not.
#   bash tests/sanitize.sh            # build and run
#   bash tests/sanitize.sh --build    # build only
set -euo pipefail
cd "$(dirname "$0")/.."
bash .ci/setup
compilers=()
fuzz=OFF
if command -v clang++ >/dev/null; then
  compilers=(-DCMAKE_CXX_COMPILER=clang++)
  fuzz=ON
fi
if [ ! -f build-sanitize/build.ninja ]; then
  cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${compilers[@]}" \
    -DISOTRACE_SANITIZE=address,undefined -DISOTRACE_FUZZ=$fuzz >/dev/null
fi
cmake --build build-sanitize -j2
[ "${1:-}" = "--build" ] && exit 0
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Leaks inside third-party libraries only (see the file); print_suppressions=0
# keeps the corpus's "no sanitizer text" check meaningful.
export LSAN_OPTIONS=suppressions=$PWD/tests/sanitizer_suppressions.txt:print_suppressions=0
# Left out: the image regressions (above) and the installed-package test,
# whose consumer is built without the sanitizers and so cannot link the
# instrumented library. (Sanitized tests run 3-10x slower: tests/CMakeLists.txt
# gives them longer timeouts.)
ctest --test-dir build-sanitize --output-on-failure -j2 -E 'SceneRegression|installed_geometry_package'
