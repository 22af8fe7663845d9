#include "renderer/image/image_comparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace isotrace;

namespace {
Image image(int w, int h, std::vector<float> rgb) {
    Image i;
    i.width = w;
    i.height = h;
    i.rgb = std::move(rgb);
    return i;
}
}  // namespace

TEST(ImageComparison, MetricsMatchHandComputedValues) {
    // Two pixels; the test image differs by 0.1 in one channel of pixel 0
    // and by 0.3 in all channels of pixel 1.
    const Image ref = image(2, 1, {0.5f, 0.5f, 0.5f, 1.0f, 1.0f, 1.0f});
    const Image test = image(2, 1, {0.6f, 0.5f, 0.5f, 1.3f, 1.3f, 1.3f});
    const ImageDifference d = compareImages(test, ref, 0.2);
    // Squared errors: 0.01 + 3 * 0.09 = 0.28 over 6 values.
    EXPECT_NEAR(d.rmse, std::sqrt(0.28 / 6), 1e-6);
    EXPECT_NEAR(d.meanAbsolute, (0.1 + 0.9) / 6, 1e-6);
    EXPECT_NEAR(d.maxAbsolute, 0.3, 1e-6);
    EXPECT_NEAR(d.psnr, -20 * std::log10(std::sqrt(0.28 / 6)), 1e-4);
    // Pixel 0: 0.1 <= 0.2 * 0.55; pixel 1: 0.3 > 0.2 * 1.05.
    EXPECT_DOUBLE_EQ(d.fractionOver, 0.5);
    EXPECT_NEAR(d.relativeMse, (0.01 / 0.26 + 3 * 0.09 / 1.01) / 6, 1e-6);
}

TEST(ImageComparison, EqualImagesHaveInfinitePsnr) {
    const Image a = image(1, 1, {0.2f, 0.3f, 0.4f});
    const ImageDifference d = compareImages(a, a);
    EXPECT_EQ(d.rmse, 0.0);
    EXPECT_TRUE(std::isinf(d.psnr));
}

TEST(ImageComparison, CountsNonFinitePixels) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Image a = image(3, 1, {0, 0, 0, nan, 0, 0, 0, 0, INFINITY});
    const Image b = image(3, 1, {0, 0, 0, 0, 0, 0, 0, 0, 0});
    const ImageDifference d = compareImages(a, b);
    EXPECT_EQ(d.nonFinite, 2);
    EXPECT_EQ(d.firstNonFiniteX, 1);
    EXPECT_EQ(d.firstNonFiniteY, 0);
}

TEST(ImageComparison, DifferentSizesAreRefused) {
    EXPECT_THROW(compareImages(image(1, 1, {0, 0, 0}), image(1, 2, {0, 0, 0, 0, 0, 0})), std::invalid_argument);
}
