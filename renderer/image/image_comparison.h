// Differences between two images of the same size: the metrics that
// `isotrace compare` and the regression suite report.
#pragma once

#include <string>

#include "renderer/image/film.h"

namespace isotrace {

struct ImageDifference {
    double rmse = 0.0;
    double meanAbsolute = 0.0;
    double maxAbsolute = 0.0;
    double relativeMse = 0.0;  ///< mean of (a - b)^2 / (b^2 + 0.01)
    double psnr = 0.0;         ///< against a peak of 1 (infinite for equal images)
    double fractionOver = 0.0; ///< pixels with any channel differing by more than the pixel threshold
    double referenceMean = 0.0;
    long long nonFinite = 0;   ///< NaN or infinite values in either image
    int firstNonFiniteX = -1, firstNonFiniteY = -1;
};

/// `pixelThreshold` is absolute plus relative to the reference value:
/// |a - b| > pixelThreshold * (|b| + 0.05) counts a pixel as different.
/// Throws std::invalid_argument when sizes differ.
ImageDifference compareImages(const Image& test, const Image& reference, double pixelThreshold = 0.1);

/// How far `test` differs from `reference` measured against the Monte Carlo
/// noise of `test`, estimated from `secondSeed`, a render of the same scene
/// with another seed: the mean over 4x4 blocks and channels of the squared
/// block-mean difference over its expected variance. About 1 where the two
/// differ only by noise (or less, where they share samples), far above 3
/// for a change even smaller than one pixel's noise. Throws
/// std::invalid_argument when sizes differ.
double noiseScore(const Image& test, const Image& reference, const Image& secondSeed);

}  // namespace isotrace
