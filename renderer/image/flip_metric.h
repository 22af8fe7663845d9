// FLIP, the perceptual image difference of Andersson et al., "FLIP: A
// Difference Evaluator for Alternating Images" (HPG 2020), and its HDR
// variant ("Visualizing Errors in Rendered High Dynamic Range Images",
// Eurographics 2021). Per-pixel errors lie in [0, 1]: what a viewer flipping
// between the two images at the given viewing distance would notice.
#pragma once

#include <vector>

#include "renderer/image/film.h"

namespace isotrace {

/// Pixels per degree of visual angle for a monitor `widthMeters` wide with
/// `pixelsX` columns seen from `distanceMeters`.
double pixelsPerDegree(double distanceMeters, double widthMeters, double pixelsX);
/// The papers' default: a 0.7 m wide 4K monitor seen from 0.7 m (67 ppd).
inline double defaultPixelsPerDegree() { return pixelsPerDegree(0.7, 0.7, 3840.0); }

struct FlipResult {
    int width = 0, height = 0;
    std::vector<float> errors;  ///< row-major, one value in [0, 1] per pixel
    double mean = 0.0;
    // HDR-FLIP only: the exposure range (stops) and how many were compared.
    double startExposure = 0.0, stopExposure = 0.0;
    int exposures = 0;
};

/// LDR-FLIP of two images holding linear RGB; values are clamped to [0, 1]
/// (the displayable range) first. Throws std::invalid_argument on
/// different sizes.
FlipResult ldrFlip(const Image& test, const Image& reference, double pixelsPerDegree = defaultPixelsPerDegree());

/// HDR-FLIP: LDR-FLIP of ACES-tone-mapped exposures from the one that maps
/// the reference's brightest pixel to 0.85 to the one that maps its median
/// to 0.85, one stop apart (at least two), keeping the per-pixel maximum.
FlipResult hdrFlip(const Image& test, const Image& reference, double pixelsPerDegree = defaultPixelsPerDegree());

}  // namespace isotrace
