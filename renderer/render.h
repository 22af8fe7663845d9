// The render loop: tiles in parallel (TBB), every pixel's samples in one
// task, so the image is the same bits on any number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "scene.h"

namespace isotrace {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  ///< row-major, three floats per pixel
    float* pixel(int x, int y) { return &rgb[3 * (size_t(y) * width + x)]; }
    const float* pixel(int x, int y) const { return &rgb[3 * (size_t(y) * width + x)]; }
};

struct RenderOptions {
    int threads = 0;  ///< 0: all cores
    uint64_t seed = 0;
    bool quiet = false;
};

struct RenderStatistics {
    double seconds = 0.0;
    long long nonFiniteSamples = 0;  ///< discarded samples (NaN or infinite radiance)
};

Image render(const Scene& scene, const RenderOptions& options, RenderStatistics* statistics = nullptr);

}  // namespace isotrace
