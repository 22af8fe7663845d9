#include "geometry/tracing/cell_accelerator.h"

#include <gtest/gtest.h>

#include <random>

using namespace isotrace::geometry;

namespace {

// Every point of the box inside the slab lies in boxAroundBand's box, which
// lies in the box: random boxes, tilted slabs and points, most of them near
// the slab's faces (where a wrong bound would show).
TEST(CellAccelerator, BoxAroundBandHoldsEveryPointOfTheSlab) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    size_t inside = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
        const Box3 box(a.cwiseMin(b), a.cwiseMax(b));
        // Some slopes along an axis (zero components), most tilted.
        Vec3 slope(u(rng), u(rng), u(rng));
        if (trial % 5 == 0) slope[trial % 3] = 0.0;
        const PartBand band{Vec3(u(rng), u(rng), u(rng)), slope, 0.3 * u(rng), 0.05 + 0.2 * std::abs(u(rng))};
        const Box3 around = boxAroundBand(box, band);
        if (!around.isEmpty()) {
            EXPECT_TRUE(box.contains(around.lower) && box.contains(around.upper));
        }
        for (int k = 0; k < 200; ++k) {
            Vec3 p = box.lower + Vec3(0.5 * (u(rng) + 1), 0.5 * (u(rng) + 1), 0.5 * (u(rng) + 1)).cwiseProduct(box.extent());
            // Pull the point onto a face of the slab, along the slope.
            const double n2 = slope.squaredNorm();
            if (k % 2 == 0 && n2 > 0) {
                const double target = (k % 4 == 0 ? 1 : -1) * band.halfWidth;
                p += (target - band.at(p)) / n2 * slope;
            }
            if (!box.contains(p) || std::abs(band.at(p)) > band.halfWidth) continue;
            ++inside;
            ASSERT_TRUE(around.contains(p)) << "trial " << trial << " point " << p.transpose();
        }
    }
    EXPECT_GT(inside, size_t(50000));  // the test saw points, many on the faces
}

// A slab across one axis bounds the box along that axis to its own
// thickness: 2 halfWidth / |slope| around its plane (plus the rounding slack).
TEST(CellAccelerator, BoxAroundBandIsTightAcrossAnAxisAlignedSlab) {
    const Box3 box(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    const PartBand band{Vec3(0, 0, 0.2), Vec3(0, 0, 2.0), 0.0, 0.1};  // |2 (z - 0.2)| <= 0.1
    const Box3 around = boxAroundBand(box, band);
    EXPECT_NEAR(around.lower.z(), 0.15, 1e-8);
    EXPECT_NEAR(around.upper.z(), 0.25, 1e-8);
    EXPECT_EQ(around.lower.x(), -1.0);
    EXPECT_EQ(around.upper.y(), 1.0);
    // A slab beside the box: nothing of it is left.
    EXPECT_TRUE(boxAroundBand(box, {Vec3(0, 0, 3), Vec3(0, 0, 1), 0.0, 0.5}).isEmpty());
    // No band known: the box itself.
    const Box3 same = boxAroundBand(box, PartBand{});
    EXPECT_EQ(same.lower, box.lower);
    EXPECT_EQ(same.upper, box.upper);
}

}  // namespace
