#include "geometry/mesh_simplifier.h"

#include <gtest/gtest.h>

#include "geometry/field_parser.h"
#include "geometry/marching_cubes.h"
#include "geometry/mesh_analysis.h"
#include "geometry/polygonizer.h"

using namespace isotrace::geometry;

namespace {
FieldProgram compile(const std::string& json) {
    return FieldLibrary(Json::object(), "/fields", "test").compileDescription(Json::parse(json), "");
}
}  // namespace

// Simplification keeps topology (manifold, watertight, same genus), keeps
// every vertex and face centroid within the tolerance, and removes most
// triangles where the surface is flat or gently curved.
TEST(MeshSimplifier, KeepsTopologyAndToleranceWithFarFewerTriangles) {
    struct Case {
        const char* json;
        long long euler;
    };
    for (const Case& c : {Case{R"({"type": "sphere", "radius": 1})", 2},
                          Case{R"({"type": "torus", "major": 1, "minor": 0.3})", 0},
                          Case{R"({"type": "difference", "of": [{"type": "box", "size": [2, 1, 1]},
                                  {"type": "cylinder", "radius": 0.3, "height": 2}]})", 0}}) {
        const FieldProgram field = compile(c.json);
        MarchingCubesOptions o;
        o.resolution = 64;
        o.sharpFeatures = true;
        IndexedMesh m = marchingCubes(field, field.bounds(), o);
        const size_t before = m.triangles.size();
        const double tolerance = 0.004;
        simplifyMesh(m, field, {.maxDistance = tolerance});
        const MeshTopology t = analyzeTopology(m);
        const MeshAccuracy a = measureAccuracy(m, field);
        EXPECT_TRUE(t.watertight()) << c.json;
        EXPECT_TRUE(t.manifold()) << c.json;
        EXPECT_TRUE(t.oriented()) << c.json;
        EXPECT_EQ(t.eulerCharacteristic, c.euler) << c.json;
        EXPECT_LT(m.triangles.size(), before / 4) << c.json;
        EXPECT_LE(a.maxVertexDistance, tolerance) << c.json;
    }
}

TEST(Polygonizer, RefusesUnboundedFieldsAndAbsurdResolutions) {
    EXPECT_THROW(polygonize(compile(R"({"type": "plane"})"), {}), std::invalid_argument);
    PolygonizeOptions huge;
    huge.resolution = 1 << 20;
    EXPECT_THROW(polygonize(compile(R"({"type": "sphere", "radius": 1})"), huge), std::invalid_argument);
    PolygonizeOptions zero;
    zero.resolution = -1;
    EXPECT_THROW(polygonize(compile(R"({"type": "sphere", "radius": 1})"), zero), std::invalid_argument);
}

TEST(Polygonizer, EmptyFieldGivesAnEmptyMeshAndAWarning) {
    const auto r = polygonize(compile(R"({"type": "intersection", "of": [{"type": "sphere", "radius": 1},
                                           {"type": "sphere", "center": [5, 0, 0], "radius": 1}]})"), {});
    EXPECT_TRUE(r.mesh.triangles.empty());
    EXPECT_FALSE(r.warnings.empty());
}

TEST(Polygonizer, ToleranceChoosesTheResolution) {
    const FieldProgram torus = compile(R"({"type": "torus", "major": 1, "minor": 0.3})");
    PolygonizeOptions o;
    o.tolerance = 1e-3;
    const auto r = polygonize(torus, o);
    EXPECT_LE(measureAccuracy(r.mesh, torus).maxCentroidDistance, 1e-3);
    EXPECT_TRUE(r.warnings.empty());
}
