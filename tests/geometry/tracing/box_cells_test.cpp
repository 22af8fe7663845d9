// Boxes met in closed form (slabs, edge cylinders, corner balls) must agree
// with the general sphere tracer on every ray: sharp and rounded, turned,
// carving (the complement a difference leaves), and rounded as far as it
// goes (a rounding equal to the half size: no flat faces left).
#include <gtest/gtest.h>

#include "support/compile_field.h"
#include "support/same_hits.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(BoxCells, SharpBoxAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "box", "center": [0.1, -0.2, 0.3], "size": [1.5, 1, 2]})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 0);  // convex: rays leaving it hit nothing
}

TEST(BoxCells, RoundedTurnedBoxAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "transform", "rotate": {"axis": [1, 2, 0.5], "angle": 35},
        "translate": [0.2, -0.1, 0.3], "of": {"type": "box", "size": [1.5, 1, 2], "rounding": 0.3}})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 0);
}

TEST(BoxCells, FullyRoundedBoxAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "box", "size": [1, 1, 2], "rounding": 0.5})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 0);
}

TEST(BoxCells, CarvingBoxAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "difference", "of": [{"type": "sphere", "radius": 1},
        {"type": "box", "center": [0.5, 0.5, 0.5], "size": [1.2, 1.2, 1.2], "rounding": 0.15}]})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 30);
}
