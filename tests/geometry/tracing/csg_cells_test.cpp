// Sharp CSG trees of spheres, boxes and ring tori traced by set operations
// on each shape's exact spans must agree with the general sphere tracer on
// every ray. Only the CSG accelerator is offered, so it takes every cell,
// the edges where operands meet included.
#include <gtest/gtest.h>

#include <random>

#include "geometry/tracing/csg_cells.h"
#include "geometry/tracing/implicit_surface.h"
#include "support/compile_field.h"
#include "support/same_hits.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

namespace {

ImplicitSurfaceOptions csgOnly() { return isotrace::testing::onlyAccelerator<CsgCellAccelerator>(); }

void expectCsgAgreesWithMarching(const char* description, int minimumSecondaryHits) {
    const FieldProgram program = compileField(description);
    const ImplicitSurface surface(program, csgOnly());
    // Every cell that holds surface is taken.
    EXPECT_EQ(surface.acceleratedCellCount(), surface.cells().size()) << description;
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, minimumSecondaryHits, 0.999, csgOnly());
}

}  // namespace

TEST(CsgCells, SphereMinusTorusAgreesWithMarching) {
    // Rays leaving the carved groove meet the sphere and the groove again.
    expectCsgAgreesWithMarching(R"({"type": "difference", "of": [{"type": "sphere", "radius": 1},
        {"type": "torus", "major": 1, "minor": 0.35}]})", 30);
}

TEST(CsgCells, SphereAndRoundedBoxAgreesWithMarching) {
    expectCsgAgreesWithMarching(R"({"type": "intersection", "of": [{"type": "sphere", "radius": 1.15},
        {"type": "box", "size": [1.6, 1.6, 1.6], "rounding": 0.2}]})", 0);
}

TEST(CsgCells, TurnedUnionMinusScaledSphereAgreesWithMarching) {
    // Placements differ per leaf (turned box, scaled sphere): t is shared.
    expectCsgAgreesWithMarching(R"({"type": "difference", "of": [
        {"type": "union", "of": [
            {"type": "transform", "rotate": {"axis": [1, 2, 0.5], "angle": 30}, "of": {"type": "box", "size": [1.4, 1, 1]}},
            {"type": "sphere", "center": [0.6, 0.3, 0], "radius": 0.6}]},
        {"type": "transform", "scale": [0.5, 1.5, 0.5], "translate": [0.2, 0, 0.3], "of": {"type": "sphere", "radius": 0.6}}]})",
                                30);
}

TEST(CsgCells, OverlappingUnionAgreesWithMarching) {
    // Cells inside both operands: a ray enters them inside the solid and
    // leaves at the later of the two exits.
    expectCsgAgreesWithMarching(R"({"type": "union", "of": [{"type": "box", "size": [1.6, 1.2, 1.2], "rounding": 0.1},
        {"type": "sphere", "center": [0.5, 0.2, 0], "radius": 0.8}]})", 0);
}

// Rays that start inside the solid (refraction, and the way out of a glass
// CSG part) must leave where the last overlapping operand ends.
TEST(CsgCells, RaysFromInsideLeaveWhereMarchingDoes) {
    const FieldProgram program = compileField(R"({"type": "difference", "of": [
        {"type": "union", "of": [{"type": "box", "size": [1.6, 1.2, 1.2], "rounding": 0.1},
            {"type": "sphere", "center": [0.5, 0.2, 0], "radius": 0.8},
            {"type": "torus", "center": [-0.4, 0, 0], "major": 0.7, "minor": 0.25}]},
        {"type": "sphere", "center": [-0.2, 0.5, 0.4], "radius": 0.35}]})");
    ImplicitSurfaceOptions marching;
    marching.cellAccelerators.clear();
    const ImplicitSurface fast(program, csgOnly()), exact(program, marching);
    ASSERT_GT(fast.acceleratedCellCount(), 0u);
    const double size = fast.bounds().extent().norm();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> n;
    int tested = 0;
    while (tested < 400) {
        const Vec3 p = fast.bounds().lower + fast.bounds().extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        if (!(program.value(p) < -0.02)) continue;
        const Vec3 d = Vec3(n(rng), n(rng), n(rng)).normalized();
        const TraceResult a = fast.intersect(p, d, 0.0, 1e30), b = exact.intersect(p, d, 0.0, 1e30);
        ASSERT_EQ(a.hit, b.hit) << "ray " << tested;
        ASSERT_TRUE(a.hit);
        ASSERT_NEAR(a.t, b.t, 1e-5 * size) << "ray " << tested;
        ++tested;
    }
}

TEST(CsgCells, TorusIntersectedWithTorusAgreesWithMarching) {
    // Two tori: up to two spans each, four ends for the set operations.
    expectCsgAgreesWithMarching(R"({"type": "union", "of": [{"type": "torus", "major": 1, "minor": 0.3},
        {"type": "transform", "rotate": {"axis": [1, 0, 0], "angle": 90}, "translate": [1, 0, 0],
         "of": {"type": "torus", "major": 1, "minor": 0.3}}]})", 50);
}

TEST(CsgCells, SmoothBlendsAndOtherShapesAreDeclined) {
    const CsgCellAccelerator accelerator;
    const Box3 cell(Vec3::Constant(-2), Vec3::Constant(2));
    for (const char* description : {
             R"({"type": "smooth_union", "radius": 0.2, "of": [{"type": "sphere", "radius": 1}, {"type": "sphere", "center": [1, 0, 0], "radius": 1}]})",
             R"({"type": "union", "of": [{"type": "sphere", "radius": 1}, {"type": "ellipsoid", "radii": [1, 0.5, 0.5]}]})",
             R"({"type": "union", "of": [{"type": "sphere", "radius": 1}, {"type": "torus", "major": 0.5, "minor": 0.8}]})"})
        EXPECT_FALSE(accelerator.accelerate(compileField(description), cell, 4.0).has_value()) << description;
    EXPECT_TRUE(accelerator.accelerate(compileField(R"({"type": "union", "of": [{"type": "sphere", "radius": 1},
        {"type": "box", "size": [1, 1, 1]}]})"), cell, 4.0).has_value());
}
