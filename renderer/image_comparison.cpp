#include "renderer/image_comparison.h"

#include <cmath>
#include <limits>
#include <stdexcept>

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

}  // namespace isotrace
