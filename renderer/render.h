// The render loop: tiles in parallel (TBB), every pixel's samples in one
// task, so the image is the same bits on any number of threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene.h"

namespace isotrace {

/// Pixels of a frame, or of a window of it (a crop or tile): pixel (0, 0)
/// of the image is pixel (x, y) of the full frame.
struct Image {
    int width = 0, height = 0;
    int x = 0, y = 0;                      ///< the window's place in the full frame
    int fullWidth = 0, fullHeight = 0;     ///< the full frame (0: same as width, height)
    std::vector<float> rgb;  ///< row-major, three floats per pixel
    /// Further channels (AOVs), `extraChannels.size()` floats per pixel.
    std::vector<std::string> extraChannels;
    std::vector<float> extra;
    float* pixel(int x, int y) { return &rgb[3 * (size_t(y) * width + x)]; }
    float* extraPixel(int x, int y) { return &extra[extraChannels.size() * (size_t(y) * width + x)]; }
    const float* extraPixel(int x, int y) const { return &extra[extraChannels.size() * (size_t(y) * width + x)]; }
    const float* pixel(int x, int y) const { return &rgb[3 * (size_t(y) * width + x)]; }
};

/// A window of the frame: columns [x0, x1) and rows [y0, y1).
struct PixelWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct RenderOptions {
    int threads = 0;  ///< 0: all cores
    /// Render only this window of the frame (empty: the whole frame). Every
    /// pixel gets the same bits as in a whole render.
    PixelWindow crop;
    /// Arbitrary output variables of the first hit, averaged over a pixel's
    /// samples: "albedo", "normal", "depth", "id" (object index, -1 for
    /// none; the first sample's) and "steps" (sphere-tracing steps).
    std::vector<std::string> aovs;
    uint64_t seed = 0;
    bool quiet = false;
};

struct RenderStatistics {
    double seconds = 0.0;
    long long nonFiniteSamples = 0;  ///< discarded samples (NaN or infinite radiance)
};

Image render(const Scene& scene, const RenderOptions& options, RenderStatistics* statistics = nullptr);

}  // namespace isotrace
