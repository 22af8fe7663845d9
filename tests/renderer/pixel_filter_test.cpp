#include "renderer/pixel_filter.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace isotrace;

// Offsets are the inverse of the filter's CDF: for the Gaussian truncated
// to [-r, r], CDF(x) = (erf(x / (sigma sqrt 2)) / erf(r / (sigma sqrt 2)) + 1) / 2
// must give back u from the centre to the tails (from a tabulated start,
// one step of Halley's method is to reach double precision).
TEST(PixelFilter, GaussianOffsetsInvertTheTruncatedCdf) {
    for (const auto& [sigma, radius] : {std::pair{0.5, 1.5}, std::pair{0.3, 2.0}, std::pair{2.0, 1.0}}) {
        PixelFilter filter{FilterType::Gaussian, radius, sigma};
        const double scale = sigma * std::sqrt(2.0), total = std::erf(radius / scale);
        for (double u : {0.0, 1e-9, 1e-4, 0.01, 0.1, 0.25, 0.4999, 0.5, 0.6, 0.9, 0.999, 1 - 1e-9, 0.12345, 0.7071}) {
            const Eigen::Vector2d offset = filter.sampleOffset({u, 1 - u});
            ASSERT_LE(std::abs(offset.x()), radius);
            EXPECT_NEAR((std::erf(offset.x() / scale) / total + 1) / 2, u, 1e-13) << "sigma " << sigma << " u " << u;
            // Symmetric, where 1 - u is exact enough: near u = 1e-9 the CDF is
            // so flat that its rounding moves the offset by 1e-9.
            if (u >= 1e-4 && u <= 0.999) EXPECT_NEAR(offset.y(), -offset.x(), 1e-9);
        }
    }
}

TEST(PixelFilter, BoxOffsetsAreUniform) {
    PixelFilter filter{FilterType::Box, 0.5, 0.5};
    EXPECT_EQ(filter.sampleOffset({0.0, 0.5}), Eigen::Vector2d(-0.5, 0.0));
    EXPECT_EQ(filter.sampleOffset({0.75, 0.25}), Eigen::Vector2d(0.25, -0.25));
}
