// Render time of hand.off turned into a variational implicit surface,
// sphere traced through its local models, against hand.off itself as
// triangles, in one run: the issue's setting is 640x480, 16 spp, path.
//
//   variational_render [width [spp]]
//
// Loading (the fit is cached; loading builds the BVH, or for the implicit
// the surface cells and their models) is timed once and reported apart
// from rendering: the two renders alternate for kRounds rounds, and the
// ratio is the median of the rounds' ratios.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "bench_support.h"
#include "renderer/render.h"
#include "renderer/scene_loader.h"

using namespace isotrace;

constexpr int kRounds = 5;

int main(int argc, char** argv) {
    const int width = argc > 1 ? std::atoi(argv[1]) : 640, height = width * 3 / 4;
    const int spp = argc > 2 ? std::atoi(argv[2]) : 16;
    const std::string scenes = std::string(ISOTRACE_SOURCE_DIR) + "/scenes";
    auto scene = [&](const char* object) {
        return geometry::Json::parse(R"({"camera": {"from": [0.2, 0.4, 1.6], "to": [0, 0, 0], "fov": 40},
          "integrator": {"type": "path", "max_depth": 4},
          "materials": {"skin": {"type": "diffuse", "albedo": [0.78, 0.58, 0.46]}},
          "fields": {"smooth_hand": {"type": "variational", "mesh": "meshes/hand.off"}},
          "objects": [)" + std::string(object) + R"(],
          "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})");
    };
    std::printf("hand.off at %dx%d, %d spp, path (max depth 4), 2 threads\n", width, height, spp);
    const char* objects[2] = {R"({"mesh": "meshes/hand.off", "material": "skin"})",
                              R"({"field": "smooth_hand", "as": "implicit", "material": "skin"})"};
    const char* names[2] = {"triangles (hand.off)", "variational implicit"};
    double load[2];
    std::unique_ptr<Scene> loaded[2];
    for (int i = 0; i < 2; ++i) {
        SceneOverrides overrides;
        overrides.width = width;
        overrides.height = height;
        overrides.samplesPerPixel = spp;
        // Once untimed, so that the fit is in the cache.
        loadSceneDescription(scene(objects[i]), scenes + "/bench.json", overrides);
        const auto start = std::chrono::steady_clock::now();
        loaded[i] = loadSceneDescription(scene(objects[i]), scenes + "/bench.json", overrides);
        load[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    RenderOptions options;
    options.threads = 2;
    options.seed = 1;
    options.quiet = true;
    // The two renders alternate, so that both see the same drift of a shared
    // machine; the ratio is the median of the rounds' ratios.
    std::vector<double> seconds[2], ratios;
    for (int round = 0; round < kRounds; ++round) {
        for (int i = 0; i < 2; ++i) {
            const auto start = std::chrono::steady_clock::now();
            render(*loaded[i], options);
            seconds[i].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
        ratios.push_back(seconds[1].back() / seconds[0].back());
    }
    double renderTime[2];
    for (int i = 0; i < 2; ++i) {
        renderTime[i] = bench::median(seconds[i]);
        std::printf("  %-22s load %7.3f s   render %8.3f s (median of %d)\n", names[i], load[i], renderTime[i], kRounds);
    }
    std::printf("  implicit / triangles: render %.2fx (median of the rounds' ratios; %.2f to %.2f), load + render %.2fx\n",
                bench::median(ratios), *std::min_element(ratios.begin(), ratios.end()),
                *std::max_element(ratios.begin(), ratios.end()),
                (load[1] + renderTime[1]) / (load[0] + renderTime[0]));
    return 0;
}
