// MPU implicit surfaces from scans: fit, load and render time against the
// same surface polygonized (and, for a polygon model, its own triangles),
// in one run, plus the marching steps of primary rays and of rays leaving
// the surface (bounces and shadow rays start there).
//
//   mpu_render [width [spp]]        (defaults: 320, 4; the issue's setting is 640 16)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "bench_support.h"
#include "geometry/tracing/implicit_surface.h"
#include "renderer/camera.h"
#include "renderer/integrator.h"
#include "renderer/render.h"
#include "renderer/scene_loader.h"

using namespace isotrace;

namespace {

struct Steps {
    double primary = 0, leaving = 0;
};

// Mean steps of primary rays and of one cosine-spread ray leaving each hit.
Steps countSteps(const Scene& scene, int width, int height) {
    const PerspectiveCamera camera(scene.camera, width, height);
    geometry::TraceCounters& counters = geometry::threadTraceCounters();
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    Steps s;
    size_t hits = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint64_t before = counters.steps;
            SurfaceHit hit;
            if (!scene.intersect(camera.generateRay(x + 0.5, y + 0.5, {0, 0}), INFINITY, hit)) continue;
            s.primary += double(counters.steps - before);
            // A direction in the hemisphere around the normal.
            const Vec3 n = hit.geometricNormal;
            Vec3 d(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng) * 2 - 1);
            d = (d.normalized() + n).normalized();
            before = counters.steps;
            SurfaceHit next;
            scene.intersect({offsetOrigin(hit.position, n, d), d}, INFINITY, next);
            s.leaving += double(counters.steps - before);
            ++hits;
        }
    s.primary /= double(std::max<size_t>(hits, 1));
    s.leaving /= double(std::max<size_t>(hits, 1));
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    const int width = argc > 1 ? std::atoi(argv[1]) : 320, height = width * 3 / 4;
    const int spp = argc > 2 ? std::atoi(argv[2]) : 4;
    const std::string scenes = std::string(ISOTRACE_SOURCE_DIR) + "/scenes";
    struct Case {
        const char* name;
        const char* field;   // the MPU description
        const char* camera;
        const char* source;  // the input's own triangles, if any
    };
    const Case cases[] = {
        {"kitten.xyz (5,210 points)", R"({"type": "mpu", "points": "scans/kitten.xyz"})",
         R"({"from": [0.05, 0.25, 1.1], "to": [0, 0, 0], "fov": 35})", nullptr},
    };
    std::printf("MPU surfaces at %dx%d, %d spp, path (max depth 4), 2 threads\n", width, height, spp);
    for (const Case& c : cases) {
        auto scene = [&](const std::string& object) {
            return geometry::Json::parse(std::string(R"({"camera": )") + c.camera + R"(,
              "integrator": {"type": "path", "max_depth": 4},
              "materials": {"clay": {"type": "diffuse", "albedo": [0.7, 0.6, 0.5]}},
              "fields": {"scan": )" + c.field + R"(},
              "objects": [)" + object + R"(],
              "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})");
        };
        std::printf("%s\n", c.name);
        const std::string objects[2] = {R"({"field": "scan", "as": "implicit", "material": "clay"})",
                                        R"({"field": "scan", "as": "mesh", "resolution": 256, "material": "clay"})"};
        const char* names[2] = {"MPU implicit", "polygonized (256)"};
        double renderTime[2];
        for (int i = 0; i < 2; ++i) {
            SceneOverrides overrides;
            overrides.width = width;
            overrides.height = height;
            overrides.samplesPerPixel = spp;
            auto start = std::chrono::steady_clock::now();
            loadSceneDescription(scene(objects[i]), scenes + "/bench.json", overrides);  // fits (first time)
            const double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            start = std::chrono::steady_clock::now();
            const auto loaded = loadSceneDescription(scene(objects[i]), scenes + "/bench.json", overrides);
            const double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            RenderOptions options;
            options.threads = 2;
            options.seed = 1;
            options.quiet = true;
            renderTime[i] = bench::medianSeconds(3, [&] { render(*loaded, options); });
            std::printf("  %-20s first load %6.3f s, load %6.3f s, render %8.3f s (median of 3)", names[i], first, load,
                        renderTime[i]);
            if (i == 0) {
                const Steps s = countSteps(*loaded, width, height);
                std::printf("; steps per hit: primary %.1f, leaving the surface %.1f", s.primary, s.leaving);
            }
            std::printf("\n");
        }
        std::printf("  implicit / polygonized: render %.2fx\n", renderTime[0] / renderTime[1]);
    }
    return 0;
}
