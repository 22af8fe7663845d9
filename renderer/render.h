// The render loop: tiles in parallel (TBB), every pixel's samples in one
// task, so the image is the same bits on any number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "renderer/image/film.h"
#include "renderer/scene.h"

namespace isotrace {

struct RenderOptions {
    int threads = 0;  ///< 0: all cores
    /// Render only this window of the frame (empty: the whole frame). Every
    /// pixel gets the same bits as in a whole render.
    PixelWindow crop;
    /// Arbitrary output variables of the first hit, averaged over a pixel's
    /// samples: "albedo", "normal", "depth", "id" (object index, -1 for
    /// none; the first sample's) and "steps" (sphere-tracing steps); see
    /// AovLayout in film.h.
    std::vector<std::string> aovs;
    uint64_t seed = 0;
    bool quiet = false;
    /// Called with `end` whenever window rows [previous end, end) are final,
    /// in increasing order, never two calls at once, on the render thread
    /// that finished them: an EXR writer compresses them there while the
    /// other threads render on. Bands are whole rows of 16-pixel tiles; the
    /// last call has end == image.height. An exception thrown here stops
    /// the render and is rethrown by render().
    std::function<void(const Image& image, int end)> rowsFinished;
};

struct RenderStatistics {
    double seconds = 0.0;
    long long nonFiniteSamples = 0;  ///< discarded samples (NaN or infinite radiance)
};

Image render(const Scene& scene, const RenderOptions& options, RenderStatistics* statistics = nullptr);

/// Rows of tiles rendered together: a band's tiles are taken column by
/// column, so a tile's neighbour above is a few tiles back, not a whole row.
/// The surface (Embree's tree, an MPU field's parts) a tile's rays touch is
/// then mostly still cached for the tile below: the 37,934-vertex MPU model
/// of bench/mpu_render renders in 0.98x the time (15 interleaved rounds,
/// 2 threads; its triangles, whose tree is small, in the same time).
constexpr int kTileBandRows = 4;
/// The tile (row-major index) taken `order`-th: bands of kTileBandRows rows
/// of tiles from the top, each column by column from the left.
int tileInRenderOrder(int order, int tilesX, int tilesY);

}  // namespace isotrace
