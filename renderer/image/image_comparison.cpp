#include "renderer/image/image_comparison.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace isotrace {

ImageDifference compareImages(const Image& test, const Image& reference, double pixelThreshold) {
    if (test.width != reference.width || test.height != reference.height)
        throw std::invalid_argument("image sizes differ: " + std::to_string(test.width) + "x" +
                                    std::to_string(test.height) + " against " + std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height));
    ImageDifference d;
    double sumSquared = 0.0, sumAbsolute = 0.0, sumRelative = 0.0, sumReference = 0.0;
    long long values = 0, over = 0;
    for (int y = 0; y < test.height; ++y) {
        for (int x = 0; x < test.width; ++x) {
            const float* a = test.pixel(x, y);
            const float* b = reference.pixel(x, y);
            bool pixelOver = false, pixelBad = false;
            for (int c = 0; c < 3; ++c) {
                if (!std::isfinite(a[c]) || !std::isfinite(b[c])) {
                    pixelBad = true;
                    continue;
                }
                const double diff = double(a[c]) - double(b[c]);
                sumSquared += diff * diff;
                sumAbsolute += std::abs(diff);
                sumRelative += diff * diff / (double(b[c]) * b[c] + 0.01);
                sumReference += b[c];
                d.maxAbsolute = std::max(d.maxAbsolute, std::abs(diff));
                if (std::abs(diff) > pixelThreshold * (std::abs(b[c]) + 0.05)) pixelOver = true;
                ++values;
            }
            if (pixelBad) {
                if (d.nonFinite == 0) {
                    d.firstNonFiniteX = x;
                    d.firstNonFiniteY = y;
                }
                ++d.nonFinite;
            }
            if (pixelOver) ++over;
        }
    }
    if (values > 0) {
        d.rmse = std::sqrt(sumSquared / values);
        d.meanAbsolute = sumAbsolute / values;
        d.relativeMse = sumRelative / values;
        d.referenceMean = sumReference / values;
    }
    d.psnr = d.rmse > 0 ? -20.0 * std::log10(d.rmse) : std::numeric_limits<double>::infinity();
    d.fractionOver = double(over) / (double(test.width) * test.height);
    return d;
}

namespace {

// Per-pixel variance of a render, from two renders with different seeds:
// E[(a1 - a2)^2] = 2 sigma^2, averaged over a 5x5 window to tame the
// estimate's own noise.
std::vector<double> varianceFromPair(const Image& a1, const Image& a2) {
    std::vector<double> raw(a1.rgb.size()), smooth(a1.rgb.size());
    for (size_t i = 0; i < raw.size(); ++i) {
        const double d = double(a1.rgb[i]) - double(a2.rgb[i]);
        raw[i] = std::isfinite(d) ? 0.5 * d * d : 0.0;
    }
    for (int y = 0; y < a1.height; ++y)
        for (int x = 0; x < a1.width; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0;
                int n = 0;
                for (int dy = -2; dy <= 2; ++dy)
                    for (int dx = -2; dx <= 2; ++dx) {
                        const int u = x + dx, v = y + dy;
                        if (u < 0 || v < 0 || u >= a1.width || v >= a1.height) continue;
                        sum += raw[3 * (size_t(v) * a1.width + u) + c];
                        ++n;
                    }
                smooth[3 * (size_t(y) * a1.width + x) + c] = sum / n;
            }
    return smooth;
}

}  // namespace

double noiseScore(const Image& test, const Image& reference, const Image& secondSeed) {
    if (test.width != reference.width || test.height != reference.height || test.width != secondSeed.width ||
        test.height != secondSeed.height)
        throw std::invalid_argument("noiseScore: images of different sizes");
    const std::vector<double> variance = varianceFromPair(test, secondSeed);
    // The reference is taken to carry the same noise as the test render,
    // so a pixel's difference has variance 2 sigma^2. Differences are
    // averaged over 4x4 blocks first: noise shrinks there by 4 while a
    // real change does not, so a change too small to see in one pixel
    // still stands out. Pixels are sampled independently, so pure noise
    // scores about 1.
    constexpr int kBlock = 4;
    double sum = 0;
    size_t count = 0;
    for (int by = 0; by < test.height; by += kBlock)
        for (int bx = 0; bx < test.width; bx += kBlock)
            for (int ch = 0; ch < 3; ++ch) {
                double diff = 0, var = 0;
                int n = 0;
                for (int y = by; y < std::min(by + kBlock, test.height); ++y)
                    for (int x = bx; x < std::min(bx + kBlock, test.width); ++x) {
                        const size_t i = 3 * (size_t(y) * test.width + x) + ch;
                        const double d = double(test.rgb[i]) - double(reference.rgb[i]);
                        if (!std::isfinite(d)) continue;
                        diff += d;
                        var += 2.0 * variance[i];
                        ++n;
                    }
                // Noise-free blocks that also agree (a plain background)
                // carry no evidence either way.
                if (n == 0 || (var == 0 && diff == 0)) continue;
                diff /= n;
                var /= double(n) * n;
                sum += diff * diff / (var + 1e-12);
                ++count;
            }
    return count ? sum / count : 0.0;
}

}  // namespace isotrace
