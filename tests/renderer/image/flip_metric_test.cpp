// FLIP against values worked out by hand. On uniform images the contrast
// filters change nothing and there are no edges or points, so the error is
// the redistributed HyAB distance of the two colours alone:
//   Hunt-adjusted Lab of linear white = (100, 0, 0), of black = (0, 0, 0);
//   HyAB = 100, 100^0.7 = 25.119; c_max = HyAB(green, blue)^0.7 = 41.276;
//   25.119 > 0.4 c_max, so 0.95 + (25.119 - 16.510) / (41.276 - 16.510) * 0.05 = 0.96738.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/image/flip_metric.h"

using namespace isotrace;

namespace {

Image uniform(int width, int height, float r, float g, float b) {
    Image image;
    image.width = width;
    image.height = height;
    for (int i = 0; i < width * height; ++i) image.rgb.insert(image.rgb.end(), {r, g, b});
    return image;
}

double maxError(const FlipResult& f) {
    double m = 0;
    for (float e : f.errors) m = std::max(m, double(e));
    return m;
}

}  // namespace

TEST(Flip, DefaultViewingConditionsGive67PixelsPerDegree) {
    // 0.7 m * (3840 px / 0.7 m) * pi / 180.
    EXPECT_NEAR(defaultPixelsPerDegree(), 67.0206, 1e-4);
}

TEST(Flip, IdenticalImagesHaveNoError) {
    Image a = uniform(24, 16, 0.2f, 0.5f, 0.7f);
    for (int x = 0; x < 12; ++x)
        for (int y = 0; y < 16; ++y) a.pixel(x, y)[0] = 0.9f;  // an edge, so the feature pipeline runs
    EXPECT_EQ(maxError(ldrFlip(a, a)), 0.0);
    EXPECT_EQ(maxError(hdrFlip(a, a)), 0.0);
}

TEST(Flip, UniformImagesMatchHandComputedColourErrors) {
    // Hand-computed as in the file comment.
    EXPECT_NEAR(ldrFlip(uniform(8, 8, 1, 1, 1), uniform(8, 8, 0, 0, 0)).mean, 0.96738, 1e-4);
    // Grey 0.5 against 0.25: L* 76.07 and 57.08, HyAB 18.99, ^0.7 = 7.862 < 16.51: 0.95 * 7.862 / 16.51.
    EXPECT_NEAR(ldrFlip(uniform(8, 8, 0.5f, 0.5f, 0.5f), uniform(8, 8, 0.25f, 0.25f, 0.25f)).mean, 0.45185, 1e-4);
    // Red against green, the chroma term at work.
    EXPECT_NEAR(ldrFlip(uniform(8, 8, 1, 0, 0), uniform(8, 8, 0, 1, 0)).mean, 0.98666, 1e-4);
    // Values above 1 are clamped to the display's range in LDR-FLIP.
    EXPECT_NEAR(ldrFlip(uniform(8, 8, 7, 7, 7), uniform(8, 8, 0, 0, 0)).mean, 0.96738, 1e-4);
    // Symmetric in its arguments for uniform images.
    EXPECT_NEAR(ldrFlip(uniform(8, 8, 0, 0, 0), uniform(8, 8, 1, 1, 1)).mean, 0.96738, 1e-4);
}

TEST(Flip, HdrExposuresFollowTheReference) {
    // Reference 1 everywhere: brightest and median agree, so both ends of the
    // exposure range map 1 to 0.85 through ACES: x = 2.11887 (log2 = 1.0833).
    const FlipResult f = hdrFlip(uniform(8, 8, 0.5f, 0.5f, 0.5f), uniform(8, 8, 1, 1, 1));
    EXPECT_NEAR(f.startExposure, std::log2(2.11887), 1e-4);
    EXPECT_NEAR(f.stopExposure, f.startExposure, 1e-12);
    EXPECT_EQ(f.exposures, 2);
    // 0.85 against ACES(0.5 x) = 0.56445 (linear greys): L* 93.88 and 79.92.
    EXPECT_NEAR(f.mean, 0.23282, 1e-4);
    EXPECT_NEAR(hdrFlip(uniform(8, 8, 0, 0, 0), uniform(8, 8, 1, 1, 1)).mean, 0.96519, 1e-4);

    // A reference whose luminance falls from 1 to 2^-6 across 16 pixels: the
    // median (the upper of the middle two) is pixel 7 at 2^(-6 * 7 / 15), so
    // the range is 2.8 stops and takes ceil(2.8) = 3 exposures.
    Image wide = uniform(16, 1, 1, 1, 1);
    for (int x = 0; x < 16; ++x) std::fill_n(wide.pixel(x, 0), 3, std::exp2(-6.0f * x / 15));
    const FlipResult w = hdrFlip(wide, wide);
    EXPECT_NEAR(w.stopExposure - w.startExposure, 2.8, 1e-5);
    EXPECT_EQ(w.exposures, 3);

    // Black pixels count in the median, as in NVIDIA's tool: blacken pixels
    // 10..15 and the sorted values are 6 zeros, then the lit pixels 9..0;
    // the median (index 8) is still pixel 7, 2.8 stops below the brightest.
    // (The median of the lit pixels alone would be pixel 4: 1.6 stops.)
    Image blackened = wide;
    for (int x = 10; x < 16; ++x) std::fill_n(blackened.pixel(x, 0), 3, 0.0f);
    const FlipResult b = hdrFlip(blackened, blackened);
    EXPECT_NEAR(b.stopExposure - b.startExposure, 6.0 * 7 / 15, 1e-5);
    // More than half black: the median of the lit pixels stands in, finite.
    Image dark = uniform(16, 1, 0, 0, 0);
    for (int x = 0; x < 4; ++x) std::fill_n(dark.pixel(x, 0), 3, std::exp2(-float(x)));
    const FlipResult d = hdrFlip(dark, dark);
    EXPECT_TRUE(std::isfinite(d.stopExposure));
    EXPECT_NEAR(d.stopExposure - d.startExposure, 1.0, 1e-5) << "lit median: the upper middle of 1/8, 1/4, 1/2, 1";
}

TEST(Flip, LostEdgesCostMoreThanTheirColourChange) {
    // A sharp step blurred into a ramp: the colour change at the step's
    // pixels is moderate, but the edge detector sees the lost edge and the
    // error exponent 1 - dF pushes those pixels towards 1.
    Image step = uniform(32, 8, 0.1f, 0.1f, 0.1f), ramp = step;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 32; ++x) {
            if (x >= 16) std::fill_n(step.pixel(x, y), 3, 0.6f);
            std::fill_n(ramp.pixel(x, y), 3, 0.1f + 0.5f * std::clamp((x - 8.0f) / 16.0f, 0.0f, 1.0f));
        }
    const FlipResult f = ldrFlip(ramp, step);
    // Pixel 16, the step: the ramp is 0.35 there against 0.6, an error of
    // this size for colour alone.
    const double colourError = ldrFlip(uniform(4, 4, 0.35f, 0.35f, 0.35f), uniform(4, 4, 0.6f, 0.6f, 0.6f)).mean;
    EXPECT_GT(f.errors[16 + 4 * 32], colourError);
    EXPECT_LE(maxError(f), 1.0);
}

TEST(Flip, DifferentSizesAreRejected) {
    EXPECT_THROW(ldrFlip(uniform(4, 4, 0, 0, 0), uniform(4, 5, 0, 0, 0)), std::invalid_argument);
    EXPECT_THROW(hdrFlip(uniform(4, 4, 0, 0, 0), uniform(5, 4, 0, 0, 0)), std::invalid_argument);
}
