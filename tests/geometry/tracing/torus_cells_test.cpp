// Tori traced through exact roots of their quartic must agree with the
// general sphere tracer on every ray: a torus alone (rays leaving it cross
// its hole and hit it again), turned and moved, and the carving torus of a
// difference (its complement in the cells where only it is left). A spindle
// torus, whose quartic has an inner sheet, is left to the sphere tracer.
#include <gtest/gtest.h>

#include "geometry/tracing/implicit_surface.h"
#include "support/compile_field.h"
#include "support/same_hits.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(TorusCells, TorusAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "torus", "center": [0.1, 0.2, -0.1], "major": 1, "minor": 0.3})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 50);
}

TEST(TorusCells, TurnedTorusAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "transform", "rotate": {"axis": [1, 0.3, 0.2], "angle": 60},
        "translate": [0.2, -0.1, 0.3], "of": {"type": "torus", "major": 1, "minor": 0.45}})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 30);
}

TEST(TorusCells, CarvingTorusAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "difference", "of": [{"type": "sphere", "radius": 1},
        {"type": "torus", "major": 1, "minor": 0.35}]})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 30);
}

TEST(TorusCells, SpindleTorusIsMarched) {
    const ImplicitSurface spindle(compileField(R"({"type": "torus", "major": 0.5, "minor": 0.8})"));
    EXPECT_EQ(spindle.acceleratedCellCount(), 0u);
}
