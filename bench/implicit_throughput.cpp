// Sphere-tracing cost on the implicit scenes: primary rays per second on 1
// and 2 threads, mean and maximum marching steps per ray, and, in the same
// run, Embree's throughput on a 1M-triangle mesh for scale. Also: steps with
// per-cell versus one global Lipschitz bound (tangle) and node evaluations
// per ray with and without per-cell pruning (many), and on a cluster of
// 1,001 (1 - d^2/R^2)^3 blobs (bench/scenes/blob_cluster.json, the size of
// Segment Tracing's test): load time (cells built), steps and kernel
// evaluations per primary ray.
//
//   implicit_throughput [SCENES_DIR]    (default: the source tree's scenes/)
#include <cstdio>
#include <string>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "bench_support.h"
#include "geometry/tracing/implicit_surface.h"
#include "renderer/camera.h"
#include "renderer/render.h"
#include "renderer/scene_loader.h"

using namespace isotrace;

namespace {

constexpr int kWidth = 320, kHeight = 240;

struct StepStatistics {
    double meanSteps = 0, maxSteps = 0, meanEvaluations = 0;
};

// Steps of every primary ray, traced on this thread (counters are per thread).
StepStatistics countSteps(const Scene& scene) {
    const PerspectiveCamera camera(scene.camera, kWidth, kHeight);
    geometry::TraceCounters& counters = geometry::threadTraceCounters();
    StepStatistics s;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const uint64_t steps0 = counters.steps, eval0 = counters.evaluations;
            SurfaceHit hit;
            scene.intersect(camera.generateRay(x + 0.5, y + 0.5, {0, 0}), INFINITY, hit);
            const double steps = double(counters.steps - steps0);
            s.meanSteps += steps;
            s.meanEvaluations += double(counters.evaluations - eval0);
            s.maxSteps = std::max(s.maxSteps, steps);
        }
    s.meanSteps /= double(kWidth) * kHeight;
    s.meanEvaluations /= double(kWidth) * kHeight;
    return s;
}

double primaryRaysPerSecond(const Scene& scene, int threads) {
    const PerspectiveCamera camera(scene.camera, kWidth, kHeight);
    tbb::task_arena arena(threads);
    const double seconds = bench::medianSeconds(5, [&] {
        arena.execute([&] {
            tbb::parallel_for(0, kHeight, [&](int y) {
                for (int x = 0; x < kWidth; ++x) {
                    SurfaceHit hit;
                    scene.intersect(camera.generateRay(x + 0.5, y + 0.5, {0, 0}), INFINITY, hit);
                }
            });
        });
    });
    return double(kWidth) * kHeight / seconds;
}

std::unique_ptr<Scene> load(const std::string& dir, const std::string& name) {
    return loadScene(dir + "/" + name + ".json");
}

// The implicit objects of `source`, their surfaces rebuilt with `options`.
std::unique_ptr<Scene> implicitObjectsRebuilt(const Scene& source, const geometry::ImplicitSurfaceOptions& options) {
    auto scene = std::make_unique<Scene>();
    scene->camera = source.camera;
    scene->materials = source.materials;
    for (const auto& surface : source.surfaces)
        scene->surfaces.push_back(std::make_unique<geometry::ImplicitSurface>(surface->field(), options));
    for (const SceneObject& o : source.objects)
        if (o.kind == SceneObject::Kind::Implicit) scene->objects.push_back(o);
    scene->commit();
    return scene;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string dir = argc > 1 ? argv[1] : std::string(ISOTRACE_SOURCE_DIR) + "/scenes";
    std::printf("primary rays at %dx%d, median of 5 runs\n\n", kWidth, kHeight);

    // Triangle baseline, same camera distance and resolution.
    Scene triangles;
    triangles.camera.from = Vec3(0, 2.2, 3.2);
    Material m;
    triangles.materials.push_back(m);
    triangles.meshes.push_back(std::make_shared<TriangleMesh>(bench::tessellatedTorus(1000, 500, 1.0, 0.4)));
    triangles.objects.push_back(SceneObject{});
    triangles.commit();
    double triangleRate[3] = {0, 0, 0};
    for (int t : {1, 2}) triangleRate[t] = primaryRaysPerSecond(triangles, t);
    std::printf("%-10s %10s %10s %9s %9s %12s\n", "scene", "1 thread", "2 threads", "mean st.", "max st.", "vs 1M tris");
    std::printf("%-10s %7.2f M/s %7.2f M/s %9s %9s %12s\n", "1M tris", triangleRate[1] / 1e6, triangleRate[2] / 1e6, "-", "-",
                "1.00");

    for (const char* name : {"showcase", "tangle", "blobby", "many"}) {
        std::unique_ptr<Scene> scene = load(dir, name);
        const StepStatistics s = countSteps(*scene);
        const double r1 = primaryRaysPerSecond(*scene, 1), r2 = primaryRaysPerSecond(*scene, 2);
        std::printf("%-10s %7.2f M/s %7.2f M/s %9.2f %9.0f %12.2f\n", name, r1 / 1e6, r2 / 1e6, s.meanSteps, s.maxSteps,
                    r2 / triangleRate[2]);
    }

    // Local cell bounds against one global bound, on the tangle.
    {
        const std::unique_ptr<Scene> scene = load(dir, "tangle");
        geometry::ImplicitSurfaceOptions global;
        global.globalLipschitzOnly = true;
        const StepStatistics local = countSteps(*scene), g = countSteps(*implicitObjectsRebuilt(*scene, global));
        std::printf("\ntangle: mean steps per ray %.2f with cell bounds, %.2f with one global bound (%.1fx)\n",
                    local.meanSteps, g.meanSteps, g.meanSteps / std::max(local.meanSteps, 1e-9));
    }

    // Node evaluations per ray with and without per-cell pruning, on many.
    {
        const std::unique_ptr<Scene> scene = load(dir, "many");
        geometry::ImplicitSurfaceOptions noPruning;
        noPruning.pruneCells = false;
        const StepStatistics pruned = countSteps(*scene), whole = countSteps(*implicitObjectsRebuilt(*scene, noPruning));
        std::printf("many: node evaluations per ray %.0f pruned, %.0f unpruned (%.1fx fewer)\n", pruned.meanEvaluations,
                    whole.meanEvaluations, whole.meanEvaluations / std::max(pruned.meanEvaluations, 1e-9));
    }

    // A loose domain: the tangle's preset box (+-3) against one narrowed by
    // hand to +-2.3 around its surface (within +-2.27), all rays of a small
    // path-traced frame (secondary and shadow rays are where loose cells
    // cost), on this thread alone so that its counters see every step.
    {
        std::printf("\ntangle, 96x96 at 8 spp, path, 1 thread: preset domain +-3 against +-2.3 by hand\n");
        for (const std::string& path : {dir + "/tangle.json",
                                       std::string(ISOTRACE_SOURCE_DIR) + "/bench/scenes/tangle_tight_domain.json"}) {
            std::unique_ptr<Scene> scene = loadScene(path);
            scene->film.width = scene->film.height = 96;
            scene->film.samplesPerPixel = 8;
            RenderOptions options;
            options.threads = 1;
            options.quiet = true;
            geometry::TraceCounters& counters = geometry::threadTraceCounters();
            const uint64_t steps0 = counters.steps;
            const double seconds = bench::medianSeconds(3, [&] { render(*scene, options); });
            std::printf("  %-28s %.3f s, %.1f steps per sample (all rays)\n", path.substr(path.rfind('/') + 1).c_str(),
                        seconds, double(counters.steps - steps0) / (3.0 * 96 * 96 * 8));
        }
    }

    // 1,001 blobs: what cell building costs before the first ray, and what
    // each ray costs after it.
    {
        const std::string path = std::string(ISOTRACE_SOURCE_DIR) + "/bench/scenes/blob_cluster.json";
        std::unique_ptr<Scene> scene;
        const double loadSeconds = bench::medianSeconds(3, [&] { scene = loadScene(path); });
        const StepStatistics s = countSteps(*scene);
        std::printf("blob_cluster (1,001 blobs): load %.3f s, %.2f steps and %.1f kernel evaluations per ray, "
                    "%.2f M rays/s on 2 threads\n",
                    loadSeconds, s.meanSteps, s.meanEvaluations, primaryRaysPerSecond(*scene, 2) / 1e6);
    }
}
