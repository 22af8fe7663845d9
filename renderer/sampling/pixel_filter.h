// Pixel reconstruction filters, applied by importance sampling: each sample's
// film offset is drawn from the filter itself, so every sample has weight 1
// and belongs to one pixel. Pixels then never share sums across threads or
// tiles, which keeps renders bit-identical however they are split.
#pragma once

#include <Eigen/Core>

namespace isotrace {

enum class FilterType { Box, Gaussian };

struct PixelFilter {
    FilterType type = FilterType::Gaussian;
    double radius = 1.5;  ///< half-width in pixels
    double sigma = 0.5;   ///< Gaussian standard deviation in pixels

    /// Offset from the pixel centre for a uniform sample u in [0,1)^2.
    Eigen::Vector2d sampleOffset(const Eigen::Vector2d& u) const;
};

}  // namespace isotrace
