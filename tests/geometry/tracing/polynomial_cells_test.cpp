// Algebraic surfaces traced through exact roots of the polynomial along each
// ray must agree with the general sphere tracer on every ray: Goursat's
// tangle (quartic), a turned and scaled quadric, a sextic, and the presets
// of degree 12 and 16.
#include <gtest/gtest.h>

#include "geometry/description/field_parser.h"
#include "geometry/tracing/implicit_surface.h"
#include "support/compile_field.h"
#include "support/same_hits.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(PolynomialCells, TangleAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "polynomial", "preset": "tangle"})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 400, 100);
}

TEST(PolynomialCells, TransformedQuadricAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "transform", "rotate": {"axis": [1, 2, 0.5], "angle": 35}, "scale": [1, 0.6, 1.4],
        "translate": [0.2, -0.1, 0.3],
        "of": {"type": "polynomial", "terms": [[1, 2, 0, 0], [1, 0, 2, 0], [-1, 0, 0, 2], [-0.3, 0, 0, 0]],
               "domain": [[-2, -2, -2], [2, 2, 2]]}})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 20);
}

TEST(PolynomialCells, SexticAgreesWithMarching) {
    // x^6 + y^6 + z^6 - 1: a rounded cube, flat where two coordinates are
    // small (convex: rays leaving it hit nothing, so no secondary hits).
    const FieldProgram program = compileField(R"({"type": "polynomial", "terms": [[1, 6, 0, 0], [1, 0, 6, 0],
        [1, 0, 0, 6], [-1, 0, 0, 0]], "domain": [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]]})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 0);
}

// Terms mixing variables take the general expansion: Taubin's heart (degree
// 6, with x^2 y^3) and the two-holed pretzel (degree 8, with x^2 y^2).
TEST(PolynomialCells, HeartAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "polynomial", "preset": "heart"})");
    // Nearly convex: few rays return, hence more rays than the others take
    // (of 4,000, 14 secondary hits with GCC and 7 with clang, whose rounding
    // draws other random rays).
    isotrace::testing::expectSameHitsAsMarching(program, 4000, 800, 6);
}

TEST(PolynomialCells, PretzelOfDegreeEightAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "polynomial", "preset": "pretzel2"})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 200, 20);
}

// Degrees above 8, up to 16, take the same search (the sphere tracer took
// minutes over a small frame of the decocube): the decocube (degree 12, a
// product of three quartics) and the four-holed pretzel (degree 16, whose
// tube thins to 0.07 where its lobes turn).
TEST(PolynomialCells, DecocubeOfDegreeTwelveAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "polynomial", "preset": "decocube"})");
    isotrace::testing::expectSameHitsAsMarching(program, 600, 100, 20);
}

TEST(PolynomialCells, PretzelOfDegreeSixteenAgreesWithMarching) {
    const FieldProgram program = compileField(R"({"type": "polynomial", "preset": "pretzel4"})");
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 100, 10);
}

// The complement of a polynomial (what a difference leaves in the cells
// where only its carving operand matters) has the same roots, the gradient
// turned around.
TEST(PolynomialCells, ComplementAgreesWithMarching) {
    const PolynomialField tangle = polynomialPreset("tangle");
    FieldProgram program;
    program.addUnary(FieldOp::Negate, program.addLeaf(tangle));
    program.setBounds(tangle.domain);
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 400, 100);
}
