#include "geometry/meshing/mesh_refiner.h"

#include <gtest/gtest.h>

#include <set>

#include "geometry/meshing/marching_cubes.h"
#include "geometry/meshing/mesh_analysis.h"
#include "support/compile_field.h"
#include "support/marching_cubes_mesh.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;
using isotrace::testing::marchingCubesMesh;

// Refinement brings every face within the tolerance, keeps the vertices on
// the surface and the mesh conforming (watertight, manifold, oriented, same
// genus), and splits only where the surface needs it: fewer faces than a
// uniform mesh of that accuracy.
TEST(MeshRefiner, EveryFaceWithinTheToleranceAndTheTopologyKept) {
    struct Case {
        const char* json;
        long long euler;
    };
    for (const Case& c : {Case{R"({"type": "sphere", "radius": 1})", 2},
                          Case{R"({"type": "torus", "major": 1, "minor": 0.3})", 0},
                          Case{R"({"type": "polynomial", "preset": "tangle"})", -8}}) {
        const FieldProgram field = compileField(c.json);
        IndexedMesh m = marchingCubesMesh(field, 24);
        const size_t before = m.triangles.size();
        const double coarse = measureAccuracy(m, field).maxCentroidDistance;
        const double tolerance = coarse / 16;
        const RefineStatistics s = refineMesh(m, field, {.maxDistance = tolerance});
        const MeshAccuracy a = measureAccuracy(m, field);
        const MeshTopology t = analyzeTopology(m);
        EXPECT_LE(a.maxCentroidDistance, tolerance) << c.json;
        EXPECT_LE(a.maxVertexDistance, 1e-3 * tolerance) << c.json;
        EXPECT_EQ(s.facesBeyond, 0u) << c.json;
        EXPECT_EQ(s.refusedSplits, 0u) << c.json;
        EXPECT_TRUE(t.watertight()) << c.json;
        EXPECT_TRUE(t.manifold()) << c.json;
        EXPECT_TRUE(t.oriented()) << c.json;
        EXPECT_EQ(t.eulerCharacteristic, c.euler) << c.json;
        EXPECT_EQ(m.triangles.size(), before + 2 * s.splits) << c.json << ": each split of an inner edge adds two faces";
        // A uniform mesh 16 times as accurate needs 4 times shorter edges,
        // 16 times the faces; refinement stays below.
        EXPECT_GT(m.triangles.size(), 2 * before) << c.json;
        EXPECT_LT(m.triangles.size(), 16 * before) << c.json;
    }
}

// New vertices get the field's normal, like marching cubes' own.
TEST(MeshRefiner, NewVerticesGetTheFieldsNormals) {
    const FieldProgram field = compileField(R"({"type": "sphere", "radius": 1})");
    IndexedMesh m = marchingCubesMesh(field, 16);
    ASSERT_EQ(m.normals.size(), m.vertices.size());
    const size_t before = m.vertices.size();
    refineMesh(m, field, {.maxDistance = 1e-4});
    ASSERT_GT(m.vertices.size(), before);
    ASSERT_EQ(m.normals.size(), m.vertices.size());
    for (size_t v = before; v < m.vertices.size(); ++v) {
        EXPECT_NEAR(m.vertices[v].norm(), 1.0, 1e-7);
        EXPECT_NEAR(m.normals[v].dot(m.vertices[v].normalized()), 1.0, 1e-9);
    }
}

// A surface cut open where marching cubes' grid ends: the edges of the
// opening are split with their one face, on the grid's box, and no new
// boundary appears inside.
TEST(MeshRefiner, OpenMeshesStayFreeOfCracks) {
    const FieldProgram field =
        compileField(R"({"type": "sphere", "radius": 1, "bounds": [[-2, -2, -2], [2, 2, 0.5]]})");
    IndexedMesh m = marchingCubesMesh(field, 16);
    const MeshTopology before = analyzeTopology(m);
    ASSERT_GT(before.boundaryEdges, 0u) << "the test needs a boundary";
    double top = -1;
    for (const Vec3& v : m.vertices) top = std::max(top, v.z());
    const RefineStatistics s = refineMesh(m, field, {.maxDistance = 1e-4});
    ASSERT_GT(s.splits, 0u);
    const MeshTopology after = analyzeTopology(m);
    EXPECT_EQ(after.nonManifoldEdges, 0u);
    EXPECT_EQ(after.nonManifoldVertices, 0u);
    EXPECT_TRUE(after.oriented());
    // The boundary is one loop: V - E + F of a disc.
    EXPECT_EQ(after.eulerCharacteristic, before.eulerCharacteristic);
    for (const auto& tri : m.triangles)
        for (int k = 0; k < 3; ++k) ASSERT_LE(m.vertices[tri[k]].z(), top);
    EXPECT_GE(after.boundaryEdges, before.boundaryEdges);
}

// Where no split can reach the tolerance, refinement stops at the shortest
// edge it was given and says how many faces it left.
TEST(MeshRefiner, StopsAtTheShortestEdgeAndCountsWhatIsLeft) {
    const FieldProgram field = compileField(R"({"type": "sphere", "radius": 1})");
    IndexedMesh m = marchingCubesMesh(field, 8);
    auto longestEdge = [&](const std::array<uint32_t, 3>& tri) {
        double longest = 0;
        for (int k = 0; k < 3; ++k) longest = std::max(longest, (m.vertices[tri[k]] - m.vertices[tri[(k + 1) % 3]]).norm());
        return longest;
    };
    // Faces marching cubes made short already (slivers) are not split.
    std::set<std::array<uint32_t, 3>> shortBefore;
    for (const auto& tri : m.triangles)
        if (longestEdge(tri) < 0.05) shortBefore.insert(tri);
    const RefineStatistics s = refineMesh(m, field, {.maxDistance = 1e-14, .minEdgeLength = 0.05});
    ASSERT_GT(s.splits, 0u);
    EXPECT_EQ(s.facesBeyond, m.triangles.size()) << "every face is too far at 1e-14";
    // A split face's halves keep at least half its longest edge.
    for (const auto& tri : m.triangles)
        if (!shortBefore.count(tri)) {
            EXPECT_GE(longestEdge(tri), 0.02);
        }
    EXPECT_TRUE(analyzeTopology(m).watertight());
}

// An edge whose two faces run the same way along it (one turned over) is
// never split: reading them as an ordinary pair would go wrong, and splitting
// one side only would leave a crack. Here it is the longest edge of both, so
// neither face can be refined.
TEST(MeshRefiner, AnEdgeOfTwoFacesOrientedAlikeStaysWhole) {
    const FieldProgram field = compileField(R"({"type": "sphere", "radius": 1})");
    IndexedMesh m;
    m.vertices = {Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(0.6, 0, 0.8), Vec3(-0.6, 0, 0.8)};
    m.triangles = {{0, 1, 2}, {0, 1, 3}};
    const RefineStatistics r = refineMesh(m, field, {.maxDistance = 1e-3});
    EXPECT_EQ(r.splits, 0u);
    EXPECT_EQ(r.facesBeyond, 2u);
    EXPECT_EQ(m.triangles.size(), 2u);
}

// The same for an edge of three faces (a fin): refinement goes on around it.
TEST(MeshRefiner, AnEdgeOfThreeFacesStaysWhole) {
    const FieldProgram field = compileField(R"({"type": "sphere", "radius": 1})");
    IndexedMesh m = marchingCubesMesh(field, 8);
    const auto finned = m.triangles.back();
    m.vertices.push_back(Vec3(0, 0, 0));
    m.triangles.push_back({finned[1], finned[0], uint32_t(m.vertices.size() - 1)});
    const RefineStatistics r = refineMesh(m, field, {.maxDistance = 1e-4, .minEdgeLength = 0.05});
    EXPECT_GT(r.splits, 0u) << "the faces of sound edges are refined";
    size_t withEdge = 0;
    for (const auto& tri : m.triangles)
        for (int k = 0; k < 3; ++k)
            withEdge += (tri[k] == finned[0] && tri[(k + 1) % 3] == finned[1]) ||
                        (tri[k] == finned[1] && tri[(k + 1) % 3] == finned[0]);
    EXPECT_EQ(withEdge, 3u);
}

// Meshes of more than a few thousand faces are refined in blocks at once,
// then along the blocks' walls: the result is conforming and within the
// tolerance, and the same whatever the number of threads (the blocks' new
// faces join the mesh in block order, not in the order threads finish).
TEST(MeshRefiner, BlocksRefinedAtOnceGiveTheSameMeshOnAnyNumberOfThreads) {
    struct Case {
        const char* json;
        bool closed;
        long long euler;
    };
    for (const Case& c : {Case{R"({"type": "sphere", "radius": 1})", true, 2},
                          Case{R"({"type": "torus", "major": 1, "minor": 0.3})", true, 0},
                          Case{R"({"type": "sphere", "radius": 1, "bounds": [[-2, -2, -2], [2, 2, 0.5]]})", false, 1}}) {
        const FieldProgram field = compileField(c.json);
        const IndexedMesh input = marchingCubesMesh(field, 64);
        // Blocks of about 4,096 faces, two or more along each axis.
        ASSERT_GT(input.triangles.size(), 14000u) << c.json << ": the test needs more than one block";
        const double tolerance = measureAccuracy(input, field).maxCentroidDistance / 4;
        IndexedMesh one = input, two = input;
        const RefineStatistics s1 = refineMesh(one, field, {.maxDistance = tolerance, .threads = 1});
        const RefineStatistics s2 = refineMesh(two, field, {.maxDistance = tolerance, .threads = 2});
        EXPECT_GT(s1.splits, input.triangles.size() / 10) << c.json;
        EXPECT_EQ(s1.splits, s2.splits) << c.json;
        EXPECT_EQ(one.triangles, two.triangles) << c.json;
        EXPECT_EQ(one.vertices, two.vertices) << c.json;
        EXPECT_EQ(one.normals, two.normals) << c.json;
        const MeshAccuracy a = measureAccuracy(two, field);
        const MeshTopology t = analyzeTopology(two);
        EXPECT_LE(a.maxCentroidDistance, tolerance) << c.json;
        EXPECT_EQ(s2.facesBeyond, 0u) << c.json;
        EXPECT_EQ(t.watertight(), c.closed) << c.json;
        EXPECT_EQ(t.nonManifoldEdges, 0u) << c.json;
        EXPECT_TRUE(t.oriented()) << c.json;
        EXPECT_EQ(t.eulerCharacteristic, c.euler) << c.json;
        EXPECT_EQ(two.normals.size(), two.vertices.size()) << c.json;
    }
}
