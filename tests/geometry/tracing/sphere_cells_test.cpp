// Spheres traced in closed form must agree with the general sphere tracer
// on every ray: a sphere alone, turned and scaled, and the cells of a CSG
// difference where only the carving sphere is left.
#include <gtest/gtest.h>

#include "support/compile_field.h"
#include "support/same_hits.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(SphereCells, SphereAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "sphere", "center": [0.2, -0.1, 0.3], "radius": 0.8})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 0);  // convex: rays leaving it hit nothing
}

TEST(SphereCells, ScaledTurnedSphereAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "transform", "rotate": {"axis": [1, 2, 0.5], "angle": 35},
        "scale": [1, 0.6, 1.4], "translate": [0.2, -0.1, 0.3], "of": {"type": "sphere", "radius": 1}})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 0);
}

TEST(SphereCells, CarvedBoxAgreesWithMarching) {
    // The inside of the carving sphere is reached by rays from outside and
    // by the secondary rays that leave the carved hollow.
    const FieldProgram program = compileField(R"({"type": "difference", "of": [{"type": "box", "size": [2, 2, 2]},
        {"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 1}]})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 30);
}
