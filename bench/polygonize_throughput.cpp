// Polygonization cost and quality: marching cubes at 256^3 on the sphere,
// the tangle and the showcase CSG (wall time on 2 threads, triangles per
// second); the time and triangles the adaptive mesher (polygonize) needs for
// the same maximum surface distance; and render time of a field as implicit and as mesh at
// that accuracy, measured in one run.
#include <chrono>
#include <cstdio>
#include <vector>

#include "bench_support.h"
#include "geometry/description/field_parser.h"
#include "geometry/meshing/marching_cubes.h"
#include "geometry/meshing/mesh_analysis.h"
#include "geometry/meshing/polygonizer.h"
#include "renderer/render.h"
#include "renderer/scene_loader.h"

using namespace isotrace;
using namespace isotrace::geometry;

int main() {
    const std::string scenes = std::string(ISOTRACE_SOURCE_DIR) + "/scenes";
    const Json showcase = parseJsonFile(scenes + "/showcase.json");
    const FieldLibrary showcaseFields(showcase.at("fields"), "/fields", "showcase.json");
    const FieldLibrary inline_(Json::parse(R"({"sphere": {"type": "sphere", "radius": 1},
                                                 "tangle": {"type": "polynomial", "preset": "tangle"}})"),
                               "/fields", "bench");
    struct Entry {
        const char* name;
        FieldProgram field;
    };
    const Entry entries[] = {{"sphere", inline_.compile("sphere")},
                             {"tangle", inline_.compile("tangle")},
                             {"cube_minus_ball", showcaseFields.compile("cube_minus_ball")}};

    std::printf("%-16s %9s %11s %12s %14s %12s %10s %8s %8s\n", "field", "MC 256^3", "triangles", "Mtris/s", "max distance",
                "adaptive", "ratio", "time", "time/MC");
    std::printf("  (aspect ratio: longest edge over shortest altitude, 1 equilateral; worst / 99th percentile)\n");
    for (const Entry& e : entries) {
        MarchingCubesOptions o;
        o.resolution = 256;
        o.threads = 2;
        IndexedMesh mc = marchingCubes(e.field, e.field.bounds(), o);
        const double target = measureAccuracy(mc, e.field).maxCentroidDistance;
        // Adaptive, to the same bound: feature vertices on half the grid,
        // refinement, then simplification; timed alternately with marching
        // cubes (medians of 5 each), its stages timed apart within the same
        // runs.
        IndexedMesh adaptive;
        std::vector<double> extraction, refinement, simplification;
        PolygonizeOptions a;
        a.method = PolygonizeMethod::Adaptive;
        a.resolution = o.resolution;
        a.tolerance = target;
        a.threads = o.threads;
        const auto [seconds, adaptiveSeconds] = bench::interleavedMedianSeconds(
            5, [&] { mc = marchingCubes(e.field, e.field.bounds(), o); },
            [&] {
                Polygonization p = polygonize(e.field, a);
                adaptive = std::move(p.mesh);
                extraction.push_back(p.extractionSeconds);
                refinement.push_back(p.refinementSeconds);
                simplification.push_back(p.simplificationSeconds);
            });
        const MeshAccuracy mcQuality = measureAccuracy(mc, e.field), adaptiveQuality = measureAccuracy(adaptive, e.field);
        std::printf("%-16s %8.3fs %11zu %12.2f %14.2e %12zu %10.3f %7.3fs %7.2fx   (adaptive max distance %.2e)\n", e.name,
                    seconds, mc.triangles.size(), mc.triangles.size() / seconds / 1e6, target, adaptive.triangles.size(),
                    double(adaptive.triangles.size()) / double(mc.triangles.size()), adaptiveSeconds,
                    adaptiveSeconds / seconds, adaptiveQuality.maxCentroidDistance);
        std::printf("%-16s adaptive = marching cubes with feature vertices at %d^3 %.3fs + refinement %.3fs + "
                    "simplification %.3fs (%.2fx MC)\n",
                    "", a.resolution / 2, bench::median(extraction), bench::median(refinement),
                    bench::median(simplification), bench::median(simplification) / seconds);
        std::printf("%-16s aspect ratio: marching cubes %.3g / %.3g, adaptive %.3g / %.3g\n", "",
                    mcQuality.worstAspectRatio, mcQuality.aspectRatio99thPercentile, adaptiveQuality.worstAspectRatio,
                    adaptiveQuality.aspectRatio99thPercentile);
    }

    // Render time, implicit against mesh, of the comparison scene's field.
    std::printf("\nrender of scenes/comparison.json at 320x160, 16 spp, 2 threads (median of 3):\n");
    for (auto mode : {SceneOverrides::FieldMode::Implicit, SceneOverrides::FieldMode::Mesh}) {
        SceneOverrides overrides;
        overrides.fieldMode = mode;
        overrides.width = 320;
        overrides.height = 160;
        overrides.samplesPerPixel = 16;
        const auto loadStart = std::chrono::steady_clock::now();
        const auto scene = loadScene(scenes + "/comparison.json", overrides);
        const double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count();
        const double seconds = bench::medianSeconds(3, [&] { render(*scene, {.threads = 2, .seed = 1, .quiet = true}); });
        std::printf("  %-9s load %.2fs, render %.3fs\n", mode == SceneOverrides::FieldMode::Mesh ? "as mesh" : "implicit",
                    load, seconds);
    }
}
