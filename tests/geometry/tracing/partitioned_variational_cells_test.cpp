// Partitioned variational fits (interpolants blended by MPU weights) march
// through one model per interpolant and part, certifying signs with the
// models' error bounds and anchoring them with exact values near the
// surface: they must agree with the general sphere tracer on every ray, and
// sum far fewer interpolant terms per ray.
#include <gtest/gtest.h>

#include <random>

#include "geometry/tracing/implicit_surface.h"
#include "geometry/tracing/partitioned_variational_cells.h"
#include "support/compile_field.h"
#include "support/random_rays.h"
#include "support/same_hits.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

namespace {

ImplicitSurfaceOptions partitionedOnly() {
    return isotrace::testing::onlyAccelerator<PartitionedVariationalCellAccelerator>();
}

// The scanned sphere (926 points, radius 10) fitted by the partitioned
// solver, brought to radius 1.
std::string partitionedSphereScan() {
    return R"({"type": "transform", "scale": 0.1, "of": {"type": "variational", "solver": "partition", "points": ")" +
           isotrace::testing::testDataFile("sphere926.pwn") + R"("}})";
}

}  // namespace

TEST(PartitionedVariationalCells, ScannedSphereAgreesWithMarching) {
    const FieldProgram program = compileField(partitionedSphereScan());
    isotrace::testing::expectSameHitsAsMarching(program, 300, 50, 0, 0.999, partitionedOnly());
}

TEST(PartitionedVariationalCells, HermiteFitAgreesWithMarching) {
    // Gradient constraints at the points: every interpolant's models carry
    // Hermite terms.
    std::string scan = partitionedSphereScan();
    scan.insert(scan.rfind('}', scan.size() - 2), R"(, "hermite": true)");
    const FieldProgram program = compileField(scan);
    isotrace::testing::expectSameHitsAsMarching(program, 300, 50, 0, 0.999, partitionedOnly());
}

TEST(PartitionedVariationalCells, TurnedAndStretchedFitAgreesWithMarching) {
    const FieldProgram program =
        compileField(R"({"type": "transform", "scale": [1, 0.6, 1], "rotate": {"axis": [1, 1, 0], "angle": 30},
                        "translate": [0.2, 0, 0], "of": )" + partitionedSphereScan() + "}");
    isotrace::testing::expectSameHitsAsMarching(program, 300, 50, 0, 0.999, partitionedOnly());
}

// The work, counted (not timed): an exact evaluation sums every centre of
// every interpolant reaching the point, a model step 35 monomials and a few
// near terms each. The hand's interpolants hold 86 centres on average (up
// to 319); the scanned sphere's few dozen, where models save little.
TEST(PartitionedVariationalCells, SumFarFewerTermsThanMarching) {
    const FieldProgram program = compileField(R"({"type": "variational", "solver": "partition", "mesh": ")" +
                                              std::string(ISOTRACE_SOURCE_DIR) + R"(/scenes/meshes/hand.off"})");
    ImplicitSurfaceOptions marching;
    marching.cellAccelerators.clear();
    const ImplicitSurface fast(program, partitionedOnly()), exact(program, marching);
    ASSERT_GT(fast.acceleratedCellCount(), 0u);
    const double modelled = isotrace::testing::evaluationsPerRay(fast, 100),
                 marched = isotrace::testing::evaluationsPerRay(exact, 100);
    EXPECT_LT(modelled, 0.2 * marched) << "terms per ray: modelled " << modelled << ", marched " << marched;
}

TEST(PartitionedVariationalCells, DenseFitsAndMpuFitsAreLeftToTheirOwnTracers) {
    const ImplicitSurface dense(compileField(R"({"type": "transform", "scale": 0.1, "of": {"type": "variational",
        "points": ")" + isotrace::testing::testDataFile("sphere926.pwn") + R"("}})"), partitionedOnly());
    EXPECT_EQ(dense.acceleratedCellCount(), 0u);
    const ImplicitSurface mpu(compileField(R"({"type": "mpu", "points": ")" +
                                           isotrace::testing::testDataFile("sphere926.pwn") + R"("})"),
                              partitionedOnly());
    EXPECT_EQ(mpu.acceleratedCellCount(), 0u);
}

// The hand's thin fingers, whose models' errors times the weights' slopes
// would tilt a normal by degrees if hits took their gradient from the models.
TEST(PartitionedVariationalCells, HandAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "variational", "solver": "partition", "mesh": ")" +
                                              std::string(ISOTRACE_SOURCE_DIR) + R"(/scenes/meshes/hand.off"})");
    isotrace::testing::expectSameHitsAsMarching(program, 200, 40, 0, 0.999, partitionedOnly());
}
