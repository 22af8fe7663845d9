#include "renderer/render.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "renderer/camera.h"
#include "geometry/tracing/implicit_surface.h"
#include "renderer/integrator.h"
#include "renderer/platform/progress_reporter.h"

namespace isotrace {

int tileInRenderOrder(int order, int tilesX, int tilesY) {
    const int firstRow = order / (kTileBandRows * tilesX) * kTileBandRows;
    const int rows = std::min(kTileBandRows, tilesY - firstRow), inBand = order - firstRow * tilesX;
    return (firstRow + inBand % rows) * tilesX + inBand / rows;
}

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
    const AovLayout aovs(options.aovs);
    image.extraChannels = aovs.channels();
    const size_t extraCount = image.extraChannels.size();
    image.extra.assign(size_t(image.width) * image.height * extraCount, 0.0f);

    const PerspectiveCamera camera(scene.camera, film.width, film.height);
    const Integrator& integrator = *scene.integrator;
    constexpr int kTile = 16;
    const int tilesX = (image.width + kTile - 1) / kTile, tilesY = (image.height + kTile - 1) / kTile;
    ProgressReporter progress(static_cast<long long>(tilesX) * tilesY, "render", options.quiet);
    std::atomic<long long> nonFinite{0};

    // Rows of tiles go to options.rowsFinished in order, as soon as all of
    // them up to there are done. Whoever takes the turn hands over every
    // complete row in sequence; a row finished by another thread meanwhile
    // is seen by the check after the turn is given back (sequentially
    // consistent: either that check sees the row's last tile, or the
    // thread that finished it finds the turn free).
    std::vector<std::atomic<int>> tilesLeftInRow(options.rowsFinished ? tilesY : 0);
    for (auto& left : tilesLeftInRow) left = tilesX;
    std::atomic<bool> handingOver{false};
    int rowsHandedOver = 0;  // rows of tiles; guarded by handingOver
    auto handOverFinishedRows = [&] {
        while (!handingOver.exchange(true)) {
            const int first = rowsHandedOver;
            int row = first;
            while (row < tilesY && tilesLeftInRow[row] == 0) ++row;
            if (row > first) {
                try {
                    options.rowsFinished(image, std::min(row * kTile, image.height));
                } catch (...) {
                    handingOver = false;
                    throw;
                }
                rowsHandedOver = row;
            }
            handingOver = false;
            if (row == tilesY || tilesLeftInRow[row] != 0) return;
        }
    };

    // AOVs trace each sample's camera ray once more: only when asked for.
    auto writeAovs = [&](int x, int y, float* out) {
        Sampler sampler(film.sampler, options.seed);
        std::array<double, AovLayout::kMaxChannels> sum{};  // nothing allocated per pixel
        float id = -1.0f;
        for (int s = 0; s < film.samplesPerPixel; ++s) {
            sampler.startPixelSample(x, y, static_cast<uint32_t>(s));
            const Eigen::Vector2d offset = film.filter.sampleOffset(sampler.get2D());
            const Ray ray = camera.generateRay(x + 0.5 + offset.x(), y + 0.5 + offset.y(), sampler.get2D());
            geometry::TraceCounters& counters = geometry::threadTraceCounters();
            const uint64_t steps0 = counters.steps;
            SurfaceHit hit;
            const bool found = scene.intersect(ray, INFINITY, hit);
            if (aovs.has(Aov::Albedo)) {
                RGB a = RGB::Zero();
                if (found) a = scene.materials[scene.objects[hit.object].material].albedo(shadingPointOf(scene, hit, -ray.direction, hit.t * pixelSpreadAngle(scene)));
                for (int c = 0; c < 3; ++c) sum[aovs.offset(Aov::Albedo) + c] += a[c];
            }
            if (aovs.has(Aov::Normal))
                for (int c = 0; c < 3; ++c) sum[aovs.offset(Aov::Normal) + c] += found ? hit.shadingNormal[c] : 0.0;
            if (aovs.has(Aov::Depth)) sum[aovs.offset(Aov::Depth)] += found ? hit.t : 0.0;
            if (aovs.has(Aov::Id) && s == 0) id = found ? float(hit.object) : -1.0f;
            if (aovs.has(Aov::Steps)) sum[aovs.offset(Aov::Steps)] += double(counters.steps - steps0);
        }
        for (size_t k = 0; k < extraCount; ++k) out[k] = float(sum[k] / film.samplesPerPixel);
        if (aovs.has(Aov::Id)) out[aovs.offset(Aov::Id)] = id;
    };

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
                    // A pinhole's lens sample is skipped, not drawn: 3% of a
                    // 1-spp Whitted render (the CSG preview at 1920x1440).
                    Eigen::Vector2d lens = Eigen::Vector2d::Zero();
                    if (camera.usesLensSample()) lens = sampler.get2D();
                    else sampler.skip2D();
                    const Ray ray = camera.generateRay(x + 0.5 + offset.x(), y + 0.5 + offset.y(), lens);
                    const RGB L = integrator.radiance(scene, ray, sampler);
                    if (L.allFinite()) sum += L;
                    else ++dropped;
                }
                float* out = image.pixel(x - window.x0, y - window.y0);
                for (int c = 0; c < 3; ++c) out[c] = float(sum[c] / film.samplesPerPixel);
                if (extraCount) writeAovs(x, y, image.extraPixel(x - window.x0, y - window.y0));
            }
        }
        if (dropped) nonFinite += dropped;
        progress.update(1);
        if (options.rowsFinished && --tilesLeftInRow[tile / tilesX] == 0) handOverFinishedRows();
    };

    // Tiles are taken one at a time, by every thread from one counter, band
    // after band of rows (tileInRenderOrder): rows of tiles then finish
    // roughly in order, so finished rows can be handed over (and
    // compressed) while later ones render.
    // Splitting the range as parallel_for does would finish the lower half
    // of the frame long before the upper and leave the hand-over to the end.
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    const int tileCount = tilesX * tilesY;
    std::atomic<int> nextTile{0};
    std::atomic<bool> failed{false};
    arena.execute([&] {
        tbb::parallel_for(0, arena.max_concurrency(), [&](int) {
            try {
                for (int t; !failed && (t = nextTile++) < tileCount;) renderTile(tileInRenderOrder(t, tilesX, tilesY));
            } catch (...) {
                failed = true;  // the other threads stop at their next tile
                throw;
            }
        });
    });
    if (options.rowsFinished) handOverFinishedRows();  // every row is done: none is left
    progress.done();
    if (statistics) {
        statistics->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        statistics->nonFiniteSamples = nonFinite;
    }
    return image;
}

}  // namespace isotrace
