#include "geometry/meshing/mesh_simplifier.h"

#include <gtest/gtest.h>

#include "geometry/description/field_parser.h"
#include "geometry/meshing/marching_cubes.h"
#include "geometry/meshing/mesh_analysis.h"
#include "geometry/meshing/polygonizer.h"
#include "support/compile_field.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

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
        const FieldProgram field = compileField(c.json);
        MarchingCubesOptions o;
        o.resolution = 64;
        o.sharpFeatures = true;
        IndexedMesh m = marchingCubes(field, field.bounds(), o);
        const size_t before = m.triangles.size();
        const double tolerance = 0.004;
        const double centroidsBefore = measureAccuracy(m, field).maxCentroidDistance;
        simplifyMesh(m, field, {.maxDistance = tolerance});
        const MeshTopology t = analyzeTopology(m);
        const MeshAccuracy a = measureAccuracy(m, field);
        EXPECT_TRUE(t.watertight()) << c.json;
        EXPECT_TRUE(t.manifold()) << c.json;
        EXPECT_TRUE(t.oriented()) << c.json;
        EXPECT_EQ(t.eulerCharacteristic, c.euler) << c.json;
        EXPECT_LT(m.triangles.size(), before / 4) << c.json;
        EXPECT_LE(a.maxVertexDistance, tolerance) << c.json;
        // Faces the simplifier made are within the tolerance; marching cubes'
        // own faces may not be (a flat face across a sharp edge).
        EXPECT_LE(a.maxCentroidDistance, std::max(tolerance, centroidsBefore)) << c.json << " " << centroidsBefore;
    }
}

// Marching cubes leaves slivers where the surface passes near a grid corner
// (aspect ratios in the hundreds of thousands); simplification collapses or
// flips them away wherever the tolerance allows, so the adaptive mesh has
// bounded quality. At the accuracy marching cubes itself reached, on the
// tangle (whose slivers are everywhere) every triangle ends within the
// simplifier's limit of 30, and 99% within 10; the topology and the
// tolerance hold as before.
TEST(MeshSimplifier, SliversAreCollapsedOrFlippedAway) {
    const FieldProgram field = compileField(R"({"type": "polynomial", "preset": "tangle"})");
    MarchingCubesOptions o;
    o.resolution = 96;
    IndexedMesh m = marchingCubes(field, field.bounds(), o);
    const MeshAccuracy before = measureAccuracy(m, field);
    ASSERT_GT(before.worstAspectRatio, 1000.0) << "the test needs marching cubes' slivers";
    const long long euler = analyzeTopology(m).eulerCharacteristic;
    const SimplifyOptions options{.maxDistance = before.maxCentroidDistance};
    simplifyMesh(m, field, options);
    const MeshAccuracy after = measureAccuracy(m, field);
    EXPECT_LE(after.worstAspectRatio, options.maxAspectRatio);
    EXPECT_LE(after.aspectRatio99thPercentile, 10.0);
    EXPECT_LE(after.maxCentroidDistance, options.maxDistance);
    const MeshTopology t = analyzeTopology(m);
    EXPECT_TRUE(t.watertight());
    EXPECT_TRUE(t.manifold());
    EXPECT_TRUE(t.oriented());
    EXPECT_EQ(t.eulerCharacteristic, euler);
}


// Blocks of space are simplified in parallel, each touching only the faces
// wholly inside it, so the mesh is the same whatever the thread count; the
// mesh is large enough (about 37,000 vertices) to be split into blocks and
// to leave edges near their walls for the whole-mesh queue.
TEST(MeshSimplifier, ParallelBlocksGiveTheSameMeshOnAnyThreadCount) {
    const FieldProgram field = compileField(R"({"type": "polynomial", "preset": "tangle"})");
    MarchingCubesOptions o;
    o.resolution = 96;
    o.sharpFeatures = true;
    const IndexedMesh input = marchingCubes(field, field.bounds(), o);
    ASSERT_GT(input.vertices.size(), 8 * 4096u) << "the test needs more than one block";
    const double tolerance = measureAccuracy(input, field).maxCentroidDistance;
    std::vector<IndexedMesh> results;
    for (int threads : {1, 2, 3}) {
        IndexedMesh m = input;
        simplifyMesh(m, field, {.maxDistance = tolerance, .threads = threads});
        results.push_back(std::move(m));
    }
    ASSERT_LT(results[0].triangles.size(), input.triangles.size() / 4);
    for (size_t i = 1; i < results.size(); ++i) {
        EXPECT_EQ(results[i].triangles, results[0].triangles);
        EXPECT_EQ(results[i].vertices, results[0].vertices);
    }
}
