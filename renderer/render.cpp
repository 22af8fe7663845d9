#include "render.h"

#include <atomic>
#include <chrono>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "camera.h"
#include "integrator.h"
#include "progress_reporter.h"

namespace isotrace {

Image render(const Scene& scene, const RenderOptions& options, RenderStatistics* statistics) {
    const auto start = std::chrono::steady_clock::now();
    const FilmSettings& film = scene.film;
    const PixelWindow window = options.crop.empty() ? PixelWindow{0, 0, film.width, film.height} : options.crop;
    Image image;
    image.width = window.x1 - window.x0;
    image.height = window.y1 - window.y0;
    image.x = window.x0;
    image.y = window.y0;
    image.fullWidth = film.width;
    image.fullHeight = film.height;
    image.rgb.assign(size_t(image.width) * image.height * 3, 0.0f);

    const PerspectiveCamera camera(scene.camera, film.width, film.height);
    const std::unique_ptr<Integrator> integrator = makeIntegrator(scene);
    constexpr int kTile = 16;
    const int tilesX = (image.width + kTile - 1) / kTile, tilesY = (image.height + kTile - 1) / kTile;
    ProgressReporter progress(static_cast<long long>(tilesX) * tilesY, "render", options.quiet);
    std::atomic<long long> nonFinite{0};

    auto renderTile = [&](int tile) {
        // Pixel coordinates are those of the full frame: a pixel's samples
        // depend on them alone, not on the window.
        const int x0 = window.x0 + (tile % tilesX) * kTile, y0 = window.y0 + (tile / tilesX) * kTile;
        const int x1 = std::min(x0 + kTile, window.x1), y1 = std::min(y0 + kTile, window.y1);
        Sampler sampler(film.sampler, options.seed);
        long long dropped = 0;
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
                RGB sum = RGB::Zero();
                for (int s = 0; s < film.samplesPerPixel; ++s) {
                    sampler.startPixelSample(x, y, static_cast<uint32_t>(s));
                    const Eigen::Vector2d offset = film.filter.sampleOffset(sampler.get2D());
                    const Eigen::Vector2d lens = sampler.get2D();
                    const Ray ray = camera.generateRay(x + 0.5 + offset.x(), y + 0.5 + offset.y(), lens);
                    const RGB L = integrator->radiance(ray, sampler);
                    if (L.allFinite()) sum += L;
                    else ++dropped;
                }
                float* out = image.pixel(x - window.x0, y - window.y0);
                for (int c = 0; c < 3; ++c) out[c] = float(sum[c] / film.samplesPerPixel);
            }
        }
        if (dropped) nonFinite += dropped;
        progress.update(1);
    };

    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1), [&](const tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) renderTile(t);
        });
    });
    progress.done();
    if (statistics) {
        statistics->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        statistics->nonFiniteSamples = nonFinite;
    }
    return image;
}

}  // namespace isotrace
