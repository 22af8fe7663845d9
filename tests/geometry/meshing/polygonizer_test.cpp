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

// Given a resolution and a tolerance, the adaptive mesher extracts on half
// the grid and refines: asked for the accuracy marching cubes reaches on the
// whole grid, it reaches it with far fewer triangles, the topology kept.
// Without a tolerance it extracts on the whole grid (only there is that
// accuracy known) and simplifies.
TEST(Polygonizer, AdaptiveExtractsOnHalfTheGridAndRefinesToItsAccuracy) {
    const FieldProgram torus = compileField(R"({"type": "torus", "major": 1, "minor": 0.3})");
    PolygonizeOptions whole;
    whole.resolution = 64;
    const IndexedMesh uniform = polygonize(torus, whole).mesh;
    const double tolerance = measureAccuracy(uniform, torus).maxCentroidDistance;
    PolygonizeOptions o;
    o.method = PolygonizeMethod::Adaptive;
    o.resolution = 64;
    o.tolerance = tolerance;
    const auto r = polygonize(torus, o);
    EXPECT_EQ(r.resolution, 64);
    EXPECT_EQ(r.extractionResolution, 32);
    EXPECT_TRUE(r.warnings.empty());
    EXPECT_LE(measureAccuracy(r.mesh, torus).maxCentroidDistance, tolerance);
    EXPECT_LT(r.mesh.triangles.size(), uniform.triangles.size() / 2);
    const MeshTopology t = analyzeTopology(r.mesh);
    EXPECT_TRUE(t.watertight());
    EXPECT_TRUE(t.manifold());
    EXPECT_TRUE(t.oriented());
    EXPECT_EQ(t.eulerCharacteristic, 0);
    EXPECT_GT(r.refinementSeconds, 0.0);
    EXPECT_GT(r.simplificationSeconds, 0.0);

    o.tolerance = 0;
    const auto plain = polygonize(torus, o);
    EXPECT_EQ(plain.extractionResolution, 64);
    EXPECT_EQ(plain.refinementSeconds, 0.0);
    EXPECT_LE(measureAccuracy(plain.mesh, torus).maxCentroidDistance, tolerance);
    EXPECT_LT(plain.mesh.triangles.size(), uniform.triangles.size() / 2);
}

// With a tolerance, the extraction grid is the coarsest of the doubling
// search whose marching cubes comes within four times it; refinement and
// simplification take the mesh the rest of the way.
TEST(Polygonizer, AdaptiveToleranceIsMetFromACoarserGrid) {
    const FieldProgram torus = compileField(R"({"type": "torus", "major": 1, "minor": 0.3})");
    PolygonizeOptions plain, adaptive;
    plain.tolerance = adaptive.tolerance = 2e-4;
    adaptive.method = PolygonizeMethod::Adaptive;
    const auto p = polygonize(torus, plain), a = polygonize(torus, adaptive);
    EXPECT_LT(a.extractionResolution, p.extractionResolution);
    EXPECT_LE(measureAccuracy(a.mesh, torus).maxCentroidDistance, 2e-4);
    EXPECT_LE(measureAccuracy(p.mesh, torus).maxCentroidDistance, 2e-4);
    EXPECT_LT(a.mesh.triangles.size(), p.mesh.triangles.size() / 2);
    EXPECT_TRUE(a.warnings.empty());
}

// A tolerance no mesh of sensible size can meet ends the refinement at its
// limits (edges of 1/64 of a cell, sixteen times the faces) with a warning
// that says so, not a hang.
TEST(Polygonizer, AdaptiveWarnsOfATolerancePastItsReach) {
    const FieldProgram sphere = compileField(R"({"type": "sphere", "radius": 1})");
    PolygonizeOptions o;
    o.method = PolygonizeMethod::Adaptive;
    o.resolution = 16;
    o.tolerance = 1e-12;
    const auto r = polygonize(sphere, o);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("faces stay farther than the tolerance"), std::string::npos) << r.warnings[0];
    EXPECT_TRUE(analyzeTopology(r.mesh).watertight());
    EXPECT_EQ(analyzeTopology(r.mesh).eulerCharacteristic, 2);
}
