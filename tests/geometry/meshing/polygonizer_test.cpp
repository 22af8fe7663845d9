#include "geometry/meshing/polygonizer.h"

#include <gtest/gtest.h>

#include "geometry/meshing/mesh_analysis.h"
#include "support/compile_field.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(Polygonizer, RefusesUnboundedFieldsAndAbsurdResolutions) {
    EXPECT_THROW(polygonize(compileField(R"({"type": "plane"})"), {}), std::invalid_argument);
    PolygonizeOptions huge;
    huge.resolution = 1 << 20;
    EXPECT_THROW(polygonize(compileField(R"({"type": "sphere", "radius": 1})"), huge), std::invalid_argument);
    PolygonizeOptions zero;
    zero.resolution = -1;
    EXPECT_THROW(polygonize(compileField(R"({"type": "sphere", "radius": 1})"), zero), std::invalid_argument);
}

TEST(Polygonizer, EmptyFieldGivesAnEmptyMeshAndAWarning) {
    const auto r = polygonize(compileField(R"({"type": "intersection", "of": [{"type": "sphere", "radius": 1},
                                           {"type": "sphere", "center": [5, 0, 0], "radius": 1}]})"), {});
    EXPECT_TRUE(r.mesh.triangles.empty());
    EXPECT_FALSE(r.warnings.empty());
}

TEST(Polygonizer, ToleranceChoosesTheResolution) {
    const FieldProgram torus = compileField(R"({"type": "torus", "major": 1, "minor": 0.3})");
    PolygonizeOptions o;
    o.tolerance = 1e-3;
    const auto r = polygonize(torus, o);
    EXPECT_LE(measureAccuracy(r.mesh, torus).maxCentroidDistance, 1e-3);
    EXPECT_TRUE(r.warnings.empty());
}
