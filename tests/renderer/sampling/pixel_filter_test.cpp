#include "renderer/sampling/pixel_filter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace isotrace;

// Offsets are the inverse of the filter's CDF: for the Gaussian truncated
// to [-r, r], CDF(x) = (erf(x / (sigma sqrt 2)) / erf(r / (sigma sqrt 2)) + 1) / 2
// must give back u from the centre to the tails. The tails are solved
// exactly (1e-13); inside, a cubic spline of the inverse is allowed 1e-7 of
// CDF (it measures 2e-8): a bias no render can show, where a million samples
// of one pixel resolve the CDF to 1e-3. A dense sweep finds the worst u.
TEST(PixelFilter, GaussianOffsetsInvertTheTruncatedCdf) {
    for (const auto& setting : {std::pair{0.5, 1.5}, std::pair{0.3, 2.0}, std::pair{2.0, 1.0}}) {
        // Plain variables, not a structured binding: clang 14 refuses to
        // capture those in the lambda below.
        const double sigma = setting.first, radius = setting.second;
        PixelFilter filter{FilterType::Gaussian, radius, sigma};
        const double scale = sigma * std::sqrt(2.0), total = std::erf(radius / scale);
        auto cdfError = [&](double u) {
            const double x = filter.sampleOffset({u, 0.5}).x();
            EXPECT_LE(std::abs(x), radius);
            return std::abs((std::erf(x / scale) / total + 1) / 2 - u);
        };
        for (double u : {0.0, 1e-9, 1e-4, 0.001, 1 - 1e-9, 0.999})
            EXPECT_LE(cdfError(u), 1e-13) << "tail: sigma " << sigma << " u " << u;
        double worst = 0.0;
        for (int k = 0; k <= 200000; ++k) worst = std::max(worst, cdfError(k / 200000.0));
        EXPECT_LE(worst, 1e-7) << "sigma " << sigma;
        for (double u : {1e-4, 0.01, 0.1, 0.25, 0.4999, 0.5, 0.6, 0.9, 0.999, 0.12345, 0.7071}) {
            // Symmetric, where 1 - u is exact enough.
            const Eigen::Vector2d offset = filter.sampleOffset({u, 1 - u});
            EXPECT_NEAR(offset.y(), -offset.x(), 1e-7);
        }
    }
}

TEST(PixelFilter, BoxOffsetsAreUniform) {
    PixelFilter filter{FilterType::Box, 0.5, 0.5};
    EXPECT_EQ(filter.sampleOffset({0.0, 0.5}), Eigen::Vector2d(-0.5, 0.0));
    EXPECT_EQ(filter.sampleOffset({0.75, 0.25}), Eigen::Vector2d(0.25, -0.25));
}
