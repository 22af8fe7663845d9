#!/usr/bin/env bash
# The Blender add-on's test scene (tests/blender/render_engine_test.py:
# meshes, a metaball family with a negative element, an implicit CSG
# subtraction, area, sun, point and spot lights, diffuse, metal, glass and
# plastic) rendered from Blender by isotrace (export and render) and by
# Cycles, same size and samples, 2 threads, median of RUNS renders each in
# one Blender process. Cycles sees the metaballs as Blender polygonizes
# them (render resolution 0.1) and the CSG object as its empty mesh.
#
#   bash bench/blender_cycles_comparison.sh [OUT] [WIDTH] [HEIGHT] [SAMPLES] [RUNS]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/isotrace-blender-bench}
command -v blender >/dev/null || { echo "needs Blender 3.4 (apt-get install blender)"; exit 2; }
cmake --build build --target isotrace blender_addon >/dev/null
mkdir -p "$out"
export ISOTRACE_BINARY=$PWD/build/isotrace ISOTRACE_TEST_FOLDER=$out ISOTRACE_ADDON_ZIP=$PWD/build/isotrace_blender.zip
export BLENDER_USER_SCRIPTS=$out/scripts PYTHONPATH=$PWD/tests/blender
export BENCH_WIDTH=${2:-320} BENCH_HEIGHT=${3:-240} BENCH_SAMPLES=${4:-64} BENCH_RUNS=${5:-3}
blender -b --factory-startup -noaudio --python-exit-code 1 --python-expr '
import os, statistics, time
import addon_test_support as support
import render_engine_test
support.install_addon()
width, height = int(os.environ["BENCH_WIDTH"]), int(os.environ["BENCH_HEIGHT"])
samples, runs = int(os.environ["BENCH_SAMPLES"]), int(os.environ["BENCH_RUNS"])
times = {}
for engine in ("ISOTRACE", "CYCLES"):
    for run in range(runs):
        scene, _ = render_engine_test.build_scene()
        scene.render.resolution_x, scene.render.resolution_y = width, height
        scene.render.engine = engine
        scene.isotrace.samples, scene.isotrace.threads = samples, 2
        c = scene.cycles
        c.device, c.samples, c.use_denoising, c.use_adaptive_sampling = "CPU", samples, False, False
        scene.render.threads_mode, scene.render.threads = "FIXED", 2
        started = time.monotonic()
        support.render_to(scene, engine.lower())
        times.setdefault(engine, []).append(time.monotonic() - started)
i, c = statistics.median(times["ISOTRACE"]), statistics.median(times["CYCLES"])
print(f"RESULT {width}x{height}, {samples} spp, 2 threads, median of {runs}: "
      f"isotrace (export and render) {i:.2f} s, Cycles {c:.2f} s, Cycles / isotrace {c / i:.2f}x")
' 2>&1 | grep RESULT
echo "images: $out/isotrace.exr $out/cycles.exr"
