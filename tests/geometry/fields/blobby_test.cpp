#include "geometry/fields/blobby.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using namespace isotrace::geometry;

class EveryKernel : public ::testing::TestWithParam<BlobKernel> {
protected:
    BlobbyField field() const {
        BlobbyField f;
        f.kernel = GetParam();
        f.blobbiness = 3.0;
        return f;
    }
};

TEST_P(EveryKernel, FallsFromOneToZeroAtItsSupport) {
    const BlobbyField f = field();
    EXPECT_NEAR(f.kernelValue(0.0), 1.0, 1e-15);
    EXPECT_EQ(f.kernelValue(f.support()), 0.0);
    EXPECT_EQ(f.kernelValue(f.support() * 1.5), 0.0);
    EXPECT_EQ(f.kernelSlope(f.support() * 1.5), 0.0);
    double previous = 2.0;
    for (int i = 0; i <= 1000; ++i) {
        const double k = f.kernelValue(f.support() * i / 1000.0);
        EXPECT_LE(k, previous) << "kernels decrease with distance (range() relies on it), a = " << i / 1000.0;
        previous = k;
    }
}

// The slope is the derivative of the value (central differences) and
// maxKernelSlope bounds it over any interval, attaining the bound at the
// sampled maximum (so the bound is tight, not merely safe).
TEST_P(EveryKernel, SlopeIsTheDerivativeAndItsBoundHolds) {
    const BlobbyField f = field();
    const double s = f.support();
    for (int i = 1; i < 200; ++i) {
        const double a = s * i / 200.0, h = 1e-6;
        const double numeric = (f.kernelValue(a + h) - f.kernelValue(a - h)) / (2 * h);
        EXPECT_NEAR(f.kernelSlope(a), numeric, 1e-6 * (1 + std::abs(numeric))) << "a = " << a;
    }
    std::mt19937 random(7);
    std::uniform_real_distribution<double> u(0.0, 1.2 * s);
    for (int trial = 0; trial < 200; ++trial) {
        double a0 = u(random), a1 = u(random);
        if (a0 > a1) std::swap(a0, a1);
        const double bound = f.maxKernelSlope(a0, a1);
        double sampled = 0.0;
        for (int i = 0; i <= 400; ++i) sampled = std::max(sampled, std::abs(f.kernelSlope(a0 + (a1 - a0) * i / 400.0)));
        EXPECT_GE(bound, sampled * (1 - 1e-12)) << "[" << a0 << ", " << a1 << "]";
        // 1%: the metaball's |k'| peaks at a corner, where 401 samples miss
        // the peak by up to 3 (a1 - a0) / 400.
        EXPECT_LE(bound, sampled * 1.01 + 1e-12) << "[" << a0 << ", " << a1 << "]";
    }
}

INSTANTIATE_TEST_SUITE_P(Kernels, EveryKernel,
                         ::testing::Values(BlobKernel::Blinn, BlobKernel::Metaball, BlobKernel::SoftObject,
                                           BlobKernel::Poly6));

// (1 - a^2)^3 in closed form: its value, slope -6 a (1 - a^2)^2 and the
// peak slope 96 / (25 sqrt 5) at a = 1/sqrt 5.
TEST(Poly6Kernel, MatchesItsClosedForm) {
    BlobbyField f;
    f.kernel = BlobKernel::Poly6;
    EXPECT_DOUBLE_EQ(f.kernelValue(0.5), 0.421875);
    EXPECT_DOUBLE_EQ(f.kernelSlope(0.5), -6 * 0.5 * 0.75 * 0.75);
    EXPECT_DOUBLE_EQ(f.maxKernelSlope(0.0, 1.0), 96.0 / (25.0 * std::sqrt(5.0)));
    EXPECT_EQ(f.support(), 1.0);
    // One blob of radius 2 and threshold 1/8: (1 - a^2)^3 = 1/8 at a^2 = 1/2,
    // a sphere of radius sqrt(2).
    f.threshold = 0.125;
    f.blobs = {{Vec3(1, 2, 3), 2.0, 1.0}};
    EXPECT_NEAR(f.value(Vec3(1, 2, 3) + Vec3(1, 1, 0)), 0.0, 1e-15);
}

}  // namespace
