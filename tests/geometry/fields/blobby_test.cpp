#include "geometry/fields/blobby.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <cmath>
#include <memory>
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

// Blender's metaball elements: with T = 1/8 and R = 2 every element's
// surface lies sqrt 2 from its core, measured in the element's own frame.
class ShapedBlob : public ::testing::Test {
protected:
    static constexpr double kSurface = 1.4142135623730951;
    const Vec3 center{1, 2, 3};

    BlobbyField withShape(const Vec3& halfSize, const Mat3& toWorld) const {
        BlobbyField f;
        f.kernel = BlobKernel::Poly6;
        f.threshold = 0.125;
        BlobShape shape;
        shape.halfSize = halfSize;
        shape.toLocal = toWorld.inverse();
        shape.stretch = Eigen::JacobiSVD<Mat3>(shape.toLocal).singularValues()(0);
        f.shapes = std::make_shared<std::vector<BlobShape>>(1, shape);
        f.blobs = {{center, 2.0, 1.0, 0}};
        return f;
    }
};

TEST_F(ShapedBlob, SegmentCoreIsACapsule) {
    const BlobbyField f = withShape({1, 0, 0}, Mat3::Identity());
    for (const Vec3& offset : {Vec3(1 + kSurface, 0, 0), Vec3(0.3, 0, kSurface), Vec3(-0.9, -kSurface, 0),
                               Vec3(Vec3(-1, 0, 0) + kSurface * Vec3(-1, 1, 1).normalized())})
        EXPECT_NEAR(f.value(center + offset), 0.0, 1e-12) << offset.transpose();
    EXPECT_LT(f.value(center + Vec3(1.5, 0, 0)), 0.0);
    EXPECT_GT(f.value(center + Vec3(0, 1.5, 0)), 0.0);
}

TEST_F(ShapedBlob, RectangleAndBoxCoresFollowTheirAxes) {
    // Local x along world y, local y along world -x.
    Mat3 quarterTurn;
    quarterTurn << 0, -1, 0, 1, 0, 0, 0, 0, 1;
    const BlobbyField rectangle = withShape({1, 0.5, 0}, quarterTurn);
    for (const Vec3& offset : {Vec3(0, 1 + kSurface, 0), Vec3(0.5 + kSurface, 0.7, 0), Vec3(0.2, -0.9, kSurface)})
        EXPECT_NEAR(rectangle.value(center + offset), 0.0, 1e-12) << offset.transpose();
    const BlobbyField box = withShape({0.5, 0.5, 0.5}, quarterTurn);
    EXPECT_NEAR(box.value(center + Vec3(1.5, 1.5, 0.5)), 0.0, 1e-12);  // sqrt 2 from the core's edge
    EXPECT_NEAR(box.value(center + Vec3(0, 0, 0.5 + kSurface)), 0.0, 1e-12);
    EXPECT_NEAR(box.value(center), 0.125 - 1.0, 1e-15);  // inside the core the kernel is 1
}

TEST_F(ShapedBlob, ScaledAxesMakeAnEllipsoid) {
    const BlobbyField f = withShape(Vec3::Zero(), Vec3(2, 1, 0.5).asDiagonal());
    for (const Vec3& offset : {Vec3(2 * kSurface, 0, 0), Vec3(0, kSurface, 0), Vec3(0, 0, 0.5 * kSurface),
                               Vec3(Vec3(2, 1, 0.5).asDiagonal() * (kSurface * Vec3(1, -2, 1).normalized()))})
        EXPECT_NEAR(f.value(center + offset), 0.0, 1e-12) << offset.transpose();
}

// Gradients are the value's derivatives, and ranges and Lipschitz bounds
// over random boxes hold every sampled value and slope, in a sheared frame.
TEST_F(ShapedBlob, GradientRangeAndLipschitzBoundsHold) {
    Mat3 sheared;
    sheared << 1.2, 0.4, 0, -0.3, 0.8, 0.2, 0.1, 0, 1.5;
    const BlobbyField f = withShape({0.6, 0.3, 0.2}, sheared);
    std::mt19937 random(5);
    std::uniform_real_distribution<double> u(-3.5, 3.5), size(0.05, 1.5);
    for (int trial = 0; trial < 300; ++trial) {
        const Vec3 lower = center + Vec3(u(random), u(random), u(random));
        const Box3 box(lower, lower + Vec3(size(random), size(random), size(random)));
        const Interval range = f.range(box);
        const double lipschitz = f.lipschitz(box);
        for (int i = 0; i < 20; ++i) {
            const Vec3 t = (Vec3::Random() + Vec3::Ones()) / 2;
            const Vec3 p = box.lower + t.cwiseProduct(box.extent());
            Vec3 gradient;
            const double value = f.valueAndGradient(p, gradient);
            EXPECT_GE(value, range.lo - 1e-12);
            EXPECT_LE(value, range.hi + 1e-12);
            EXPECT_LE(gradient.norm(), lipschitz * (1 + 1e-12) + 1e-12);
            for (int axis = 0; axis < 3; ++axis) {
                const Vec3 h = 1e-6 * Vec3::Unit(axis);
                const double numeric = (f.value(p + h) - f.value(p - h)) / 2e-6;
                EXPECT_NEAR(gradient[axis], numeric, 1e-6 * (1 + std::abs(numeric)));
            }
        }
    }
    // The support's bounds hold the whole surface and everything inside.
    const Box3 bounds = f.bounds();
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = center + Vec3(u(random), u(random), u(random));
        if (f.value(p) <= 0) {
            EXPECT_TRUE(bounds.contains(p)) << p.transpose();
        }
    }
}

}  // namespace
