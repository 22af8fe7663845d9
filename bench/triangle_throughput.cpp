// Primary-ray and path-traced throughput of the renderer on a triangle scene
// of about 1M triangles, on 1 and 2 threads (median of 5 runs).
#include <cstdio>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "bench_support.h"
#include "renderer/camera.h"
#include "renderer/render.h"
#include "renderer/scene_builder.h"

using namespace isotrace;

int main() {
    SceneBuilder builder;
    CameraSettings view;
    view.from = Vec3(0, 2.2, 3.2);
    view.to = Vec3(0, 0, 0);
    builder.setCamera(view);
    FilmSettings film;
    film.width = 320;
    film.height = 240;
    film.samplesPerPixel = 4;
    builder.setFilm(film);
    constexpr int kMaxDepth = 4;
    builder.setIntegrator(geometry::Json{{"type", "path"}, {"max_depth", kMaxDepth}});
    SceneObject torus;
    torus.material = builder.addMaterial("clay", {{"type", "diffuse"}, {"albedo", {0.7, 0.6, 0.5}}});
    torus.shape = builder.addMesh(bench::tessellatedTorus(1000, 500, 1.0, 0.4));
    builder.addObject(torus);
    builder.addLight({{"type", "point"}, {"position", {2, 4, 3}}, {"intensity", {30, 30, 30}}});
    builder.addLight({{"type", "environment"}, {"radiance", {0.3, 0.3, 0.3}}});
    const std::unique_ptr<Scene> built = builder.build();
    const Scene& scene = *built;
    const size_t triangles = scene.meshes[0]->triangleCount();

    const PerspectiveCamera camera(scene.camera, scene.film.width, scene.film.height);
    const int w = scene.film.width, h = scene.film.height;
    std::printf("triangle scene: %zu triangles, %dx%d\n", triangles, w, h);
    for (int threads : {1, 2}) {
        tbb::task_arena arena(threads);
        const int repeats = 8;  // camera rays per pixel
        const double primary = bench::medianSeconds(5, [&] {
            arena.execute([&] {
                tbb::parallel_for(0, h, [&](int y) {
                    for (int x = 0; x < w; ++x)
                        for (int k = 0; k < repeats; ++k) {
                            SurfaceHit hit;
                            scene.intersect(camera.generateRay(x + (k + 0.5) / repeats, y + 0.5, {0, 0}), INFINITY, hit);
                        }
                });
            });
        });
        const double path = bench::medianSeconds(5, [&] { render(scene, {.threads = threads, .seed = 1, .quiet = true}); });
        const double rays = double(w) * h * repeats;
        const double samples = double(w) * h * scene.film.samplesPerPixel;
        std::printf("threads %d: primary rays %.2f Mrays/s, path tracing %.2f Msamples/s (max depth %d)\n", threads,
                    rays / primary / 1e6, samples / path / 1e6, kMaxDepth);
    }
}
