// MPU surfaces traced through their parts (polynomial roots inside bands)
// and by the general sphere tracer (per-point safe distances) must agree on
// every ray, primary and leaving the surface, for a scan and for a part
// with sharp edges.
#include <gtest/gtest.h>

#include "geometry/pointsets/mpu_field.h"
#include "geometry/tracing/implicit_surface.h"
#include "geometry/variational/constraints.h"
#include "support/drilled_cube.h"
#include "support/same_hits.h"
#include "support/turned_placement.h"

using namespace isotrace::geometry;

namespace {

void expectSameHits(const MpuField& field, int rays, const LeafPlacement& placement = {}) {
    FieldProgram program;
    program.addLeaf(MpuLeafField{std::make_shared<const MpuField>(field)}, placement);
    isotrace::testing::expectSameHitsAsMarching(program, rays, rays / 10, 10);
    isotrace::testing::expectSameHitsOnGrazingRays(program, rays, rays / 10);
}

}  // namespace

TEST(MpuCells, AgreeWithMarchingOnAScan) {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(std::string(ISOTRACE_SOURCE_DIR) + "/scenes/scans/kitten.xyz"))
        points.push_back({p.position, p.normal});
    expectSameHits(MpuField::fit(points), 600);
}

// The octree cells of one field hand their parts to one tracer, which a
// ray offered any part then finds in cache; the agreement tests above check
// that the parts keep their own lists and boxes in it.
TEST(MpuCells, CellsOfOneFieldShareOneTracer) {
    FieldProgram program;
    program.addLeaf(MpuLeafField{std::make_shared<const MpuField>(
                        MpuField::fit(isotrace::testing::sampleDrilledCube(20000, 9)))},
                    isotrace::testing::turnedPlacement(0.6, Vec3(0.05, -0.1, 0.02), 1.0));
    const ImplicitSurface surface(program);
    EXPECT_GT(surface.acceleratedCellCount(), 1000u);
    EXPECT_EQ(surface.acceleratedCellCount(), surface.cells().size());
    EXPECT_EQ(surface.tracerCount(), 1u);
}

TEST(MpuCells, AgreeWithMarchingAcrossSharpEdges) {
    expectSameHits(MpuField::fit(isotrace::testing::sampleDrilledCube(20000, 9)), 1500);
}

// Parts are clipped in the leaf's frame: under a turned, scaled placement a
// part's world box (around the turned part) holds more than the part.
TEST(MpuCells, AgreeWithMarchingWhenTurnedAndScaled) {
    expectSameHits(MpuField::fit(isotrace::testing::sampleDrilledCube(20000, 9)), 1500,
                   isotrace::testing::turnedPlacement(0.6, Vec3(0.05, -0.1, 0.02), 1.0));
}
