// The Taylor model of an MPU field's numerator must keep within its proven
// errors everywhere in its box: value and slope along any direction,
// against N summed exactly at random points; so must a model given the
// sharp locals an outer box's model resolves to one piece. The bound on
// N's third derivatives is taken from their values at the centre where
// that is tighter, so these checks also test it. Boxes of three sizes near the
// data, on a smooth fit with general quadrics (oni) and across the creases
// of edge and corner functions (a drilled cube). The largest share of each
// bound the errors reach is reported: a bound is only useful if it is not
// wildly loose.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "geometry/pointsets/mpu_numerator_model.h"
#include "geometry/pointsets/mpu_ray_segment.h"
#include "geometry/tracing/sphere_tracer.h"
#include "geometry/variational/constraints.h"
#include "support/drilled_cube.h"
#include "support/test_data.h"

using namespace isotrace::geometry;

namespace {

// Oni's oriented points, fitted without sharp features.
std::vector<MpuPoint> oniPoints() {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(isotrace::testing::testDataFile("oni.pwn")))
        points.push_back({p.position, p.normal});
    return points;
}
MpuField smoothFit(const std::vector<MpuPoint>& points) {
    MpuOptions options;
    options.sharpFeatures = false;
    return MpuField::fit(points, options);
}

// Boxes near the data, inside the field's domain: `perSize` tries for each
// size (a fraction of the domain's diagonal, stretched by `aspect`) around
// a random point, jittered by a fifth of the size. Calls visit(box, index,
// size) for each.
template <class Visit>
void forBoxesNearData(const MpuField& field, const std::vector<MpuPoint>& points, std::initializer_list<double> sizes,
                      int perSize, const Vec3& aspect, std::mt19937& rng, Visit&& visit) {
    const Box3 domain = field.bounds();
    const double diagonal = domain.extent().norm();
    std::normal_distribution<double> n;
    for (const double size : sizes)
        for (int i = 0; i < perSize; ++i) {
            const Vec3 near = points[rng() % points.size()].position + 0.2 * size * diagonal * Vec3(n(rng), n(rng), n(rng));
            const Vec3 half = Vec3::Constant(0.5 * size * diagonal).cwiseProduct(aspect);
            const Box3 box(near - half, near + half);
            if (domain.contains(box)) visit(box, i, size);
        }
}

struct Reach {
    double value = 0.0, slope = 0.0;  ///< largest error over its bound
    double nearValue = 0.0;           ///< over the bound at the point's distance
};

void expectWithinBounds(const MpuField& field, const std::vector<MpuPoint>& points, Reach& reach,
                        size_t& resolvedCount) {
    const Box3 domain = field.bounds();
    std::mt19937 rng(3);
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<uint32_t> locals;
    int boxes = 0;
    forBoxesNearData(field, points, {0.002, 0.008, 0.03}, 150, Vec3(1.0, 0.7, 1.3), rng,
                     [&](const Box3& box, int i, double size) {
            const Vec3 near = box.center(), half = 0.5 * box.extent();
            // The box's model, alone and with the sharp locals resolved by
            // the model of an outer box, twice as large, of which it is an
            // octant.
            Box3 outer;
            outer.extend(box.lower);
            outer.extend(box.upper + box.extent());
            if (!domain.contains(outer)) return;
            ++boxes;
            field.localsTouching(outer, locals);
            const MpuLocalColumns columns(field, locals);
            const MpuNumeratorModel outerModel = fitMpuNumeratorModel(field, outer, columns);
            // The sharp locals the outer model resolves to one piece, summed
            // and bounded as single pieces by the inner box's models.
            MpuLocalColumns resolved;
            resolved.assignResolved(field, nullptr, columns.sharp(), outerModel);
            resolvedCount += resolved.singleCount();
            const MpuNumeratorModel models[2] = {fitMpuNumeratorModel(field, box, columns),
                                                 fitMpuNumeratorModel(field, box, columns, &resolved)};
            for (int k = 0; k < 160; ++k) {
                const MpuNumeratorModel& m = models[k / 80];
                ASSERT_TRUE(std::isfinite(m.valueError) && std::isfinite(m.slopeError));
                // The corners first: the remainder grows with |x - c|^3.
                const Vec3 corner(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
                const Vec3 x = near + (k % 80 < 8 ? corner : Vec3(u(rng), u(rng), u(rng))).cwiseProduct(half);
                const MpuBlendSums exact = field.blendSums(x, {locals});
                Vec3 modelGradient;
                const double model = m.at(x, &modelGradient);
                ASSERT_LE(std::abs(exact.N - model), m.valueError) << "model " << k / 80 << ", box " << i << " of size " << size;
                const Vec3 direction = Vec3(n(rng), n(rng), n(rng)).normalized();
                const double slope = std::abs((exact.gradientN - modelGradient).dot(direction));
                ASSERT_LE(slope, m.slopeError) << "model " << k / 80 << ", box " << i << " of size " << size;
                reach.value = std::max(reach.value, std::abs(exact.N - model) / m.valueError);
                reach.slope = std::max(reach.slope, slope / m.slopeError);
                // Nearer the centre, where no crease crosses the box, the
                // remainder at the point's own distance (what tracers narrow
                // a span's errors to).
                if (!std::isfinite(m.hessianError)) continue;
                const MpuTaylorRemainder atDistance =
                    mpuTaylorRemainder(m.remainderThird, (x - near).norm(), m.valueFloor, m.slopeFloor);
                ASSERT_LE(std::abs(exact.N - model), atDistance.value) << "model " << k / 80 << ", box " << i;
                ASSERT_LE(slope, atDistance.slope) << "model " << k / 80 << ", box " << i;
                reach.nearValue = std::max(reach.nearValue, std::abs(exact.N - model) / atDistance.value);
            }
        });
    EXPECT_GT(boxes, 300);
}

}  // namespace

TEST(MpuNumeratorModel, KeepsWithinItsErrorsOnASmoothFit) {
    const std::vector<MpuPoint> points = oniPoints();
    Reach reach;
    size_t resolved = 0;
    expectWithinBounds(smoothFit(points), points, reach, resolved);
    std::printf("smooth fit: errors reach %.3g of the value bound, %.3g of the slope bound, %.3g of the value bound "
                "at their distance\n",
                reach.value, reach.slope, reach.nearValue);
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

// M3, the model's bound on N's third directional derivatives over its box,
// against the third derivatives of the exact N, by central differences of
// its exact gradient (their error, about h^2 N^(5) with h a thousandth of
// the balls' radius, is far below the allowance of 1e-3). Taken where the
// locals' own bounds would be loose: from N's third derivatives at the
// centre, plus the fourth's bound times the half diagonal.
TEST(MpuNumeratorModel, BoundsTheThirdDerivativesOverItsBox) {
    const std::vector<MpuPoint> points = oniPoints();
    const MpuField field = smoothFit(points);
    const double diagonal = field.bounds().extent().norm();
    std::mt19937 rng(7);
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<uint32_t> locals;
    double reach = 0.0;
    int boxes = 0;
    // The smallest boxes are bounded by the third derivatives at their
    // centre alone: there the bound is nearly reached.
    forBoxesNearData(field, points, {1e-5, 0.002, 0.008, 0.03}, 100, Vec3::Ones(), rng,
                     [&](const Box3& box, int i, double size) {
            const Vec3 near = box.center(), half = 0.5 * box.extent();
            ++boxes;
            field.localsTouching(box, locals);
            const MpuNumeratorModel m = fitMpuNumeratorModel(field, box, MpuLocalColumns(field, locals));
            ASSERT_TRUE(std::isfinite(m.third));
            double smallestRadius = diagonal;
            for (const uint32_t l : locals) smallestRadius = std::min(smallestRadius, field.locals()[l].radius);
            const double h = 1e-3 * smallestRadius;
            for (int k = 0; k < 64; ++k) {
                const Vec3 corner(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
                const Vec3 x = near + (k < 8 ? corner : Vec3(u(rng), u(rng), u(rng))).cwiseProduct(half);
                const Vec3 d = Vec3(n(rng), n(rng), n(rng)).normalized();
                auto slope = [&](const Vec3& p) { return field.blendSums(p, {locals}).gradientN.dot(d); };
                const double third = (slope(x + h * d) - 2.0 * slope(x) + slope(x - h * d)) / (h * h);
                ASSERT_LE(std::abs(third), m.third * (1 + 1e-3)) << "box " << i << " of size " << size;
                reach = std::max(reach, std::abs(third) / m.third);
            }
        });
    EXPECT_GT(boxes, 300);
    std::printf("third derivatives reach %.3g of the bound\n", reach);
}

// A sharp local whose crease the box's model proves away from the box takes
// one piece all over it: sums that take that piece alone (what a tracer's
// part does) must equal the sums that let each local choose, anywhere in
// the box: N, its gradient, N alone, and the first root along chords.
// Boxes near the creases of the drilled cube, where pieces are resolved;
// the resolved pieces go to the vector lanes with the single-piece locals,
// except in lists too long for the lanes' row list, which sum them one by
// one: there the list is that of a large box around the small one.
TEST(MpuNumeratorModel, SharpLocalsResolvedToOnePieceSumAsBefore) {
    const std::vector<MpuPoint> points = isotrace::testing::sampleDrilledCube(20000, 5);
    const MpuField field = MpuField::fit(points);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<uint32_t> locals;
    size_t resolved = 0, roots = 0, longLists = 0;
    std::vector<uint32_t> around;
    auto compare = [&](const Box3& box, const Box3& listBox, int i, double size) {
            // The box's own locals first (the list's first sharp locals are
            // the ones resolved), then the rest of the list box's.
            field.localsTouching(box, locals);
            field.localsTouching(listBox, around);
            for (const uint32_t l : around)
                if (std::find(locals.begin(), locals.end(), l) == locals.end()) locals.push_back(l);
            longLists += locals.size() > 256;
            const MpuLocalList choosing = field.singlesFirst(locals);
            const MpuNumeratorModel m = fitMpuNumeratorModel(field, box, MpuLocalColumns(field, locals));
            const MpuLocalList taking(locals, choosing.singles, mpuResolvedSharpPieces(field, m, choosing));
            for (size_t k = 0; k < choosing.otherLocals().size(); ++k) resolved += taking.pieceOf(k) >= 0;
            const Vec3 c = box.center(), half = 0.5 * box.extent();
            for (int k = 0; k < 40; ++k) {
                const Vec3 x = c + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(half);
                const MpuBlendSums a = field.blendSums(x, choosing), b = field.blendSums(x, taking);
                // The resolved pieces join the lanes (summed in another order).
                const double scale = MpuField::kSumRelativeError * (1.0 + std::abs(a.N) + a.gradientN.norm());
                ASSERT_NEAR(b.N, a.N, scale) << "box " << i << " of size " << size;
                ASSERT_LE((b.gradientN - a.gradientN).norm(), scale) << "box " << i << " of size " << size;
                ASSERT_NEAR(field.numerator(x, taking), a.N, scale) << "box " << i << " of size " << size;
                // A chord of the box through x.
                const Vec3 unit = Vec3(u(rng), u(rng), u(rng)).normalized();
                const Vec3 from = x - 2.0 * half.norm() * unit;
                double t0 = 0.0, t1 = 4.0 * half.norm();
                if (!clipRayToBox(box, from, unit, t0, t1) || !(t1 > t0)) continue;
                const double tolerance = 1e-9 * size;
                const MpuSegmentRoot ra = firstRootAlongSegment(field, choosing, from, unit, t0, t1, tolerance);
                const MpuSegmentRoot rb = firstRootAlongSegment(field, taking, from, unit, t0, t1, tolerance);
                ASSERT_EQ(ra.hit, rb.hit) << "box " << i << " of size " << size;
                if (ra.hit) {
                    ASSERT_NEAR(ra.t, rb.t, 2.0 * tolerance) << "box " << i << " of size " << size;
                    ++roots;
                }
            }
        };
    forBoxesNearData(field, points, {0.002, 0.008, 0.03}, 150, Vec3::Ones(), rng,
                     [&](const Box3& box, int i, double size) { compare(box, box, i, size); });
    const double diagonal = field.bounds().extent().norm();
    forBoxesNearData(field, points, {0.008}, 20, Vec3::Ones(), rng, [&](const Box3& box, int i, double size) {
        compare(box, box.expanded(0.15 * diagonal), i, size);
    });
    EXPECT_GT(resolved, 1000u);  // resolved locals were summed
    EXPECT_GT(roots, 100u);      // and crossed by chords that meet the surface
    EXPECT_GT(longLists, 0u);    // lists past the lanes' row list were summed too
    std::printf("%zu sharp locals resolved to one piece, %zu roots compared, %zu long lists\n", resolved, roots,
                longLists);
}
