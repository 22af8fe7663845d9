// Cells where a variational field meets other operands march through a
// model of the variational leaf, certifying signs with its error bound:
// they must agree with the general sphere tracer on every ray, for CSG and
// blends alike, Hermite fields too, and need far fewer exact sums of the
// leaf's terms.
#include <gtest/gtest.h>

#include <random>

#include "geometry/tracing/implicit_surface.h"
#include "geometry/tracing/variational_csg_cells.h"
#include "support/compile_field.h"
#include "support/embree_scene.h"
#include "support/random_rays.h"
#include "support/same_hits.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

namespace {

ImplicitSurfaceOptions modelledCsgOnly() { return isotrace::testing::onlyAccelerator<VariationalCsgCellAccelerator>(); }

// A scanned sphere of radius 10, brought to radius 1.
std::string sphereScan() {
    return R"({"type": "transform", "scale": 0.1, "of": {"type": "variational", "points": ")" +
           isotrace::testing::testDataFile("sphere926.pwn") + R"("}})";
}

}  // namespace

TEST(VariationalCsgCells, DifferenceWithTorusAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "difference", "of": [)" + sphereScan() +
                                              R"(, {"type": "torus", "major": 1, "minor": 0.3}]})");
    isotrace::testing::expectSameHitsAsMarching(program, 800, 150, 10, 0.999, modelledCsgOnly());
}

TEST(VariationalCsgCells, UnionWithBoxAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "union", "of": [)" + sphereScan() +
                                              R"(, {"type": "box", "center": [0.8, 0.3, 0], "size": [1, 0.6, 0.6]}]})");
    isotrace::testing::expectSameHitsAsMarching(program, 800, 150, 0, 0.999, modelledCsgOnly());
}

TEST(VariationalCsgCells, SmoothUnionOfTurnedFieldAgreesWithMarching) {
    const FieldProgram program = compileField(
        R"({"type": "smooth_union", "radius": 0.2, "of": [{"type": "transform", "scale": [1, 0.7, 1],
            "rotate": {"axis": [1, 1, 0], "angle": 30}, "of": )" + sphereScan() +
        R"(}, {"type": "sphere", "center": [0.9, 0.4, 0], "radius": 0.45}]})");
    isotrace::testing::expectSameHitsAsMarching(program, 800, 150, 0, 0.999, modelledCsgOnly());
}

TEST(VariationalCsgCells, HermiteDifferenceAgreesWithMarching) {
    // Gradient constraints at the scan's points: models with Hermite terms.
    std::string hermiteScan = sphereScan();
    hermiteScan.insert(hermiteScan.rfind('}', hermiteScan.size() - 2), R"(, "hermite": true)");
    const FieldProgram program = compileField(R"({"type": "difference", "of": [)" + hermiteScan +
                                              R"(, {"type": "torus", "major": 1, "minor": 0.3}]})");
    const ImplicitSurface surface(program, modelledCsgOnly());
    EXPECT_GT(surface.acceleratedCellCount(), 0u);
    isotrace::testing::expectSameHitsAsMarching(program, 300, 80, 6, 0.999, modelledCsgOnly());
}

// The work, counted (not timed): each exact evaluation sums all the
// leaf's terms, a model step 35 monomials. Far fewer terms per ray than
// marching the exact tree at every step.
TEST(VariationalCsgCells, SumFarFewerTermsThanMarching) {
    const FieldProgram program = compileField(
        R"({"type": "smooth_union", "radius": 0.2, "of": [{"type": "transform", "scale": [1, 0.7, 1],
            "rotate": {"axis": [1, 1, 0], "angle": 30}, "of": )" + sphereScan() +
        R"(}, {"type": "sphere", "center": [0.9, 0.4, 0], "radius": 0.45}]})");
    ImplicitSurfaceOptions marching;
    marching.cellAccelerators.clear();
    const ImplicitSurface fast(program, modelledCsgOnly()), exact(program, marching);
    const double modelled = isotrace::testing::evaluationsPerRay(fast, 200),
                 marched = isotrace::testing::evaluationsPerRay(exact, 200);
    EXPECT_LT(modelled, 0.2 * marched) << "terms per ray: modelled " << modelled << ", marched " << marched;
}
