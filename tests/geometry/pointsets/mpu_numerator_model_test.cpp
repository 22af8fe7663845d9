// The Taylor model of an MPU field's numerator must keep within its proven
// errors everywhere in its box: value and slope along any direction,
// against N summed exactly at random points; so must a model that takes
// over the bounds of an outer box, and both with the sharp locals the outer
// box's model resolves to one piece. Boxes of three sizes near the
// data, on a smooth fit with general quadrics (oni) and across the creases
// of edge and corner functions (a drilled cube). The largest share of each
// bound the errors reach is reported: a bound is only useful if it is not
// wildly loose.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "geometry/pointsets/mpu_numerator_model.h"
#include "geometry/variational/constraints.h"
#include "support/drilled_cube.h"
#include "support/test_data.h"

using namespace isotrace::geometry;

namespace {

struct Reach {
    double value = 0.0, slope = 0.0;  ///< largest error over its bound
};

void expectWithinBounds(const MpuField& field, const std::vector<MpuPoint>& points, Reach& reach,
                        size_t& resolvedCount) {
    const Box3 domain = field.bounds();
    const double diagonal = domain.extent().norm();
    std::mt19937 rng(3);
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<uint32_t> locals;
    int boxes = 0;
    for (const double size : {0.002, 0.008, 0.03}) {
        for (int i = 0; i < 150; ++i) {
            const Vec3 near = points[rng() % points.size()].position + 0.2 * size * diagonal * Vec3(n(rng), n(rng), n(rng));
            const Vec3 half = Vec3::Constant(0.5 * size * diagonal).cwiseProduct(Vec3(1.0, 0.7, 1.3));
            Box3 box;
            box.extend(near - half);
            box.extend(near + half);
            if (!domain.contains(box)) continue;
            // The box's own model, and the one that takes over the bounds
            // of an outer box, twice as large, of which it is an octant.
            Box3 outer;
            outer.extend(box.lower);
            outer.extend(box.upper + box.extent());
            if (!domain.contains(outer)) continue;
            ++boxes;
            field.localsTouching(outer, locals);
            const MpuLocalColumns columns(field, locals);
            const MpuNumeratorModel outerModel = fitMpuNumeratorModel(field, outer, columns);
            // The sharp locals the outer model resolves to one piece, summed
            // and bounded as single pieces by the inner box's models.
            MpuLocalColumns resolved;
            resolved.assignResolved(field, nullptr, columns.sharp(), outerModel);
            resolvedCount += resolved.singleCount();
            const MpuNumeratorModel models[4] = {
                fitMpuNumeratorModel(field, box, columns),
                mpuNumeratorModelWithin(field, box, columns, nullptr, outerModel),
                fitMpuNumeratorModel(field, box, columns, &resolved),
                mpuNumeratorModelWithin(field, box, columns, &resolved, outerModel)};
            for (int k = 0; k < 160; ++k) {
                const MpuNumeratorModel& m = models[k / 40];
                ASSERT_TRUE(std::isfinite(m.valueError) && std::isfinite(m.slopeError));
                // The corners first: the remainder grows with |x - c|^3.
                const Vec3 corner(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
                const Vec3 x = near + (k % 40 < 8 ? corner : Vec3(u(rng), u(rng), u(rng))).cwiseProduct(half);
                const MpuBlendSums exact = field.blendSums(x, {locals});
                Vec3 modelGradient;
                const double model = m.at(x, &modelGradient);
                ASSERT_LE(std::abs(exact.N - model), m.valueError) << "model " << k / 40 << ", box " << i << " of size " << size;
                const Vec3 direction = Vec3(n(rng), n(rng), n(rng)).normalized();
                const double slope = std::abs((exact.gradientN - modelGradient).dot(direction));
                ASSERT_LE(slope, m.slopeError) << "model " << k / 40 << ", box " << i << " of size " << size;
                reach.value = std::max(reach.value, std::abs(exact.N - model) / m.valueError);
                reach.slope = std::max(reach.slope, slope / m.slopeError);
            }
        }
    }
    EXPECT_GT(boxes, 300);
}

}  // namespace

TEST(MpuNumeratorModel, KeepsWithinItsErrorsOnASmoothFit) {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(isotrace::testing::testDataFile("oni.pwn")))
        points.push_back({p.position, p.normal});
    MpuOptions options;
    options.sharpFeatures = false;
    Reach reach;
    size_t resolved = 0;
    expectWithinBounds(MpuField::fit(points, options), points, reach, resolved);
    std::printf("smooth fit: errors reach %.3g of the value bound, %.3g of the slope bound\n", reach.value,
                reach.slope);
}

TEST(MpuNumeratorModel, KeepsWithinItsErrorsAcrossCreases) {
    const std::vector<MpuPoint> points = isotrace::testing::sampleDrilledCube(20000, 5);
    MpuReport report;
    const MpuField field = MpuField::fit(points, {}, &report);
    ASSERT_GT(report.edges + report.corners, 0u);
    Reach reach;
    size_t resolved = 0;
    expectWithinBounds(field, points, reach, resolved);
    EXPECT_GT(resolved, 100u);  // sharp locals taken as one piece were tested
    std::printf("sharp fit: errors reach %.3g of the value bound, %.3g of the slope bound\n", reach.value,
                reach.slope);
}
