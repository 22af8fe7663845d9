// Rays against MPU fields solved on N's piecewise polynomial, against the
// field itself sampled densely along the same segments: the first sign
// change is found, none is skipped, and the root is a zero of the field;
// single-piece locals summed in vector lanes give the same root.
// Fits with general quadrics (oni's sparse horns) and with edge and corner
// functions (a drilled cube) cover every kind of local.
#include <gtest/gtest.h>

#include <random>

#include "geometry/pointsets/mpu_ray_segment.h"
#include "geometry/variational/constraints.h"
#include "support/drilled_cube.h"
#include "support/test_data.h"

using namespace isotrace::geometry;

namespace {

void expectFirstRootsAlongSegments(const MpuField& field, const std::vector<MpuPoint>& points, int segments) {
    const Box3 domain = field.bounds();
    const double diagonal = domain.extent().norm();
    std::mt19937 rng(7);
    std::normal_distribution<double> n;
    std::vector<uint32_t> locals;
    int found = 0;
    for (int i = 0; i < segments; ++i) {
        // A segment of a tenth of the diagonal through a point near the data.
        const Vec3 near = points[rng() % points.size()].position + 0.01 * diagonal * Vec3(n(rng), n(rng), n(rng));
        const Vec3 direction = Vec3(n(rng), n(rng), n(rng)).normalized();
        const Vec3 origin = near - 0.05 * diagonal * direction;
        double t0 = 0.0, t1 = 0.1 * diagonal;
        const Vec3 a = origin + t0 * direction, b = origin + t1 * direction;
        if (!domain.contains(a) || !domain.contains(b)) continue;
        Box3 around;
        around.extend(a);
        around.extend(b);
        field.localsTouching(around, locals);
        const double tolerance = 1e-9 * diagonal;
        // The list as it comes, and with its single-piece locals first (summed
        // in vector lanes): the same first root.
        const MpuSegmentRoot root = firstRootAlongSegment(field, {locals}, origin, direction, t0, t1, tolerance);
        const MpuSegmentRoot inLanes =
            firstRootAlongSegment(field, field.singlesFirst(locals), origin, direction, t0, t1, tolerance);
        ASSERT_EQ(inLanes.hit, root.hit) << "segment " << i;
        if (root.hit) {
            ASSERT_NEAR(inLanes.t, root.t, 2.0 * tolerance) << "segment " << i;
        }
        ASSERT_EQ(inLanes.localTerms, root.localTerms) << "segment " << i;
        constexpr int kSamples = 4000;
        const double step = (t1 - t0) / kSamples;
        double expected = -1, previous = field.value(a);
        for (int k = 1; k <= kSamples && expected < 0; ++k) {
            const double v = field.value(origin + (t0 + k * step) * direction);
            if ((v < 0) != (previous < 0)) expected = t0 + k * step;
            previous = v;
        }
        if (expected >= 0) {
            ++found;
            ASSERT_TRUE(root.hit) << "segment " << i;
            EXPECT_LE(root.t, expected + tolerance) << "segment " << i;
            EXPECT_GE(root.t, expected - step - tolerance) << "segment " << i << ": an earlier root than sampling shows";
        }
        if (root.hit) {
            // A zero of the exact field (|grad f| is about 1).
            EXPECT_LT(std::abs(field.value(origin + root.t * direction)), 1e-7 * diagonal) << "segment " << i;
        }
    }
    EXPECT_GT(found, segments / 10);
}

std::vector<MpuPoint> oni() {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(isotrace::testing::testDataFile("oni.pwn")))
        points.push_back({p.position, p.normal});
    return points;
}

}  // namespace

TEST(MpuRaySegment, FindsTheFirstRootOfSmoothFits) {
    const std::vector<MpuPoint> points = oni();
    MpuOptions options;
    options.sharpFeatures = false;
    expectFirstRootsAlongSegments(MpuField::fit(points, options), points, 400);
}

TEST(MpuRaySegment, FindsTheFirstRootAcrossSharpEdges) {
    const std::vector<MpuPoint> points = isotrace::testing::sampleDrilledCube(20000, 5);
    MpuReport report;
    const MpuField field = MpuField::fit(points, {}, &report);
    ASSERT_GT(report.edges + report.corners, 0u);
    expectFirstRootsAlongSegments(field, points, 400);
}
