// The linear and bilinear warps (environment maps sample their bilinear
// lookups with them) against their densities: Pearson's chi-square over a
// grid of cells whose expected counts integrate the density (midpoints),
// for corner values with zeros, equal values and strong slopes.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "renderer/sampling/sampling.h"
#include "support/chi_square.h"

using namespace isotrace;
using isotrace::testing::chiSquareTest;

namespace {

struct Corners {
    double a00, a10, a01, a11;
};

const Corners kCases[] = {{1, 1, 1, 1}, {0, 1, 0, 1}, {4, 0.5, 0.1, 2}, {0, 0, 0, 3}, {2000, 2000, 0.45, 0.45}};

}  // namespace

TEST(BilinearSampling, LinearWarpPassesChiSquareAgainstItsDensity) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> uniform;
    const int bins = 50, samples = 200000;
    for (const auto& [a, b] : {std::pair{1.0, 1.0}, {0.0, 1.0}, {3.0, 0.0}, {0.2, 5.0}}) {
        std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
        for (int s = 0; s < samples; ++s) {
            const double x = sampleLinear(uniform(rng), a, b);
            ASSERT_GE(x, 0.0);
            ASSERT_LT(x, 1.0);
            observed[std::min(int(x * bins), bins - 1)] += 1;
        }
        for (int k = 0; k < bins; ++k) {
            const double x = (k + 0.5) / bins;  // the density is linear: the midpoint is exact
            expected[k] = samples * ((1 - x) * a + x * b) / (0.5 * (a + b)) / bins;
        }
        const auto result = chiSquareTest(observed, expected);
        EXPECT_EQ(result.impossible, 0.0);
        EXPECT_GT(result.pValue, 0.01 / 9) << "a " << a << ", b " << b;
    }
}

TEST(BilinearSampling, BilinearWarpPassesChiSquareAgainstBilinearPdf) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> uniform;
    const int bins = 24, samples = 300000, sub = 8;
    for (const Corners& c : kCases) {
        std::vector<double> observed(bins * bins, 0.0), expected(bins * bins, 0.0);
        for (int s = 0; s < samples; ++s) {
            const Eigen::Vector2d p = sampleBilinear({uniform(rng), uniform(rng)}, c.a00, c.a10, c.a01, c.a11);
            ASSERT_TRUE(p.x() >= 0 && p.x() < 1 && p.y() >= 0 && p.y() < 1);
            observed[std::min(int(p.y() * bins), bins - 1) * bins + std::min(int(p.x() * bins), bins - 1)] += 1;
        }
        for (int y = 0; y < bins; ++y)
            for (int x = 0; x < bins; ++x) {
                double sum = 0.0;
                for (int j = 0; j < sub; ++j)
                    for (int i = 0; i < sub; ++i)
                        sum += bilinearPdf({(x + (i + 0.5) / sub) / bins, (y + (j + 0.5) / sub) / bins}, c.a00, c.a10,
                                           c.a01, c.a11);
                expected[y * bins + x] = samples * sum / (sub * sub) / (bins * bins);
            }
        const auto result = chiSquareTest(observed, expected);
        EXPECT_EQ(result.impossible, 0.0);
        EXPECT_GT(result.pValue, 0.01 / 9) << c.a00 << " " << c.a10 << " " << c.a01 << " " << c.a11;
    }
}

// The density integrates to 1 over the square.
TEST(BilinearSampling, BilinearPdfIsNormalized) {
    for (const Corners& c : kCases) {
        double sum = 0.0;
        const int n = 200;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) sum += bilinearPdf({(i + 0.5) / n, (j + 0.5) / n}, c.a00, c.a10, c.a01, c.a11);
        EXPECT_NEAR(sum / (n * n), 1.0, 1e-9);
    }
}
