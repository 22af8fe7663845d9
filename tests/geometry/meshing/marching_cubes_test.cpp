#include "geometry/meshing/marching_cubes.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "geometry/description/field_parser.h"
#include "geometry/meshing/mesh_analysis.h"
#include "support/compile_field.h"
#include "support/marching_cubes_mesh.h"
#include "support/field_catalog.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;
using isotrace::testing::marchingCubesMesh;
using isotrace::testing::CatalogEntry;
using isotrace::testing::compileCatalogEntry;
using isotrace::testing::fieldCatalog;

// Euler characteristic 2 - 2g: sphere 2, torus 0, two holes -2, four holes -6.
TEST(MarchingCubes, EulerCharacteristicMatchesGenus) {
    struct Case {
        const char* json;
        long long euler;
    };
    const Case cases[] = {
        {R"({"type": "sphere", "radius": 1})", 2},
        {R"({"type": "torus", "major": 1, "minor": 0.3})", 0},
        {R"({"type": "difference", "of": [{"type": "box", "size": [3, 1, 1]},
            {"type": "cylinder", "center": [-0.7, 0, 0], "radius": 0.3, "height": 2},
            {"type": "cylinder", "center": [0.7, 0, 0], "radius": 0.3, "height": 2}]})", -2},
        {R"({"type": "polynomial", "preset": "pretzel2"})", -2},
        {R"({"type": "polynomial", "preset": "tangle"})", -8},
    };
    for (const Case& c : cases) {
        for (bool sharp : {false, true}) {
            const IndexedMesh m = marchingCubesMesh(compileField(c.json), 64, sharp);
            const MeshTopology t = analyzeTopology(m);
            EXPECT_EQ(t.eulerCharacteristic, c.euler) << c.json << (sharp ? " (sharp)" : "");
            EXPECT_TRUE(t.watertight()) << c.json;
            EXPECT_TRUE(t.manifold()) << c.json;
        }
    }
}

// Every field of the catalog meshes to a watertight, 2-manifold, consistently
// oriented surface whose normals point outwards (along the gradient).
class EveryFieldMeshes : public ::testing::TestWithParam<CatalogEntry> {};

TEST_P(EveryFieldMeshes, WatertightManifoldAndOriented) {
    const FieldProgram field = compileCatalogEntry(GetParam());
    for (bool sharp : {false, true}) {
        const IndexedMesh m = marchingCubesMesh(field, 48, sharp);
        ASSERT_GT(m.triangles.size(), 100u);
        const MeshTopology t = analyzeTopology(m);
        EXPECT_EQ(t.boundaryEdges, 0u) << (sharp ? "sharp" : "plain");
        EXPECT_EQ(t.nonManifoldEdges, 0u);
        EXPECT_EQ(t.nonManifoldVertices, 0u);
        EXPECT_EQ(t.inconsistentEdges, 0u);
        const MeshAccuracy a = measureAccuracy(m, field);
        EXPECT_LT(a.meanNormalDeviationDegrees, 20.0) << "faces must face along the gradient";
    }
}

INSTANTIATE_TEST_SUITE_P(Catalog, EveryFieldMeshes, ::testing::ValuesIn(fieldCatalog()),
                         [](const auto& info) { return info.param.name; });

TEST(MarchingCubes, DistanceToTheSurfaceShrinksAsResolutionGrows) {
    const FieldProgram torus = compileField(R"({"type": "torus", "major": 1, "minor": 0.3})");
    double previous = INFINITY;
    for (int resolution : {16, 32, 64, 128}) {
        const MeshAccuracy a = measureAccuracy(marchingCubesMesh(torus, resolution), torus);
        EXPECT_LT(a.maxVertexDistance, 1e-6) << "vertices are refined onto the surface";
        EXPECT_LT(a.maxCentroidDistance, 0.6 * previous) << "resolution " << resolution;
        previous = a.maxCentroidDistance;
    }
}

TEST(MarchingCubes, SharpFeaturesKeepTheCornersOfABox) {
    const FieldProgram box = compileField(R"({"type": "box", "center": [0.013, 0.021, -0.017], "size": [1.2, 0.9, 0.7]})");
    const int resolution = 24;
    const double h = box.bounds().extent().maxCoeff() / resolution;
    const IndexedMesh m = marchingCubesMesh(box, resolution, true);
    for (int c = 0; c < 8; ++c) {
        const Vec3 corner = box.bounds().corner(c);
        double nearest = INFINITY;
        for (const Vec3& v : m.vertices) nearest = std::min(nearest, (v - corner).norm());
        EXPECT_LT(nearest, 0.05 * h) << "corner " << c;
    }
    // Without feature vertices the corners are cut off by about a cell.
    const IndexedMesh plain = marchingCubesMesh(box, resolution, false);
    double nearest = INFINITY;
    for (const Vec3& v : plain.vertices) nearest = std::min(nearest, (v - box.bounds().corner(0)).norm());
    EXPECT_GT(nearest, 0.2 * h);
}

// Cost follows the surface's area: doubling the resolution multiplies the
// cells visited by about 4, not 8.
TEST(MarchingCubes, VisitsOnlyCellsNearTheSurface) {
    const FieldProgram sphere = compileField(R"({"type": "sphere", "radius": 1})");
    long long visited[2];
    for (int i = 0; i < 2; ++i) {
        MarchingCubesStatistics stats;
        MarchingCubesOptions o;
        o.resolution = i == 0 ? 128 : 256;
        marchingCubes(sphere, sphere.bounds(), o, &stats);
        visited[i] = stats.cellsVisited;
    }
    EXPECT_LT(visited[1], 5 * visited[0]);
    EXPECT_LT(visited[1], 0.2 * 258.0 * 258.0 * 258.0);  // bricks of 8^3 cells along the surface
}

TEST(MarchingCubes, SameMeshOnAnyThreadCount) {
    const FieldProgram f = compileField(R"({"type": "polynomial", "preset": "tangle"})");
    MarchingCubesOptions o;
    o.resolution = 48;
    o.threads = 1;
    const IndexedMesh a = marchingCubes(f, f.bounds(), o);
    o.threads = 2;
    const IndexedMesh b = marchingCubes(f, f.bounds(), o);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles, b.triangles);
    for (size_t v = 0; v < a.vertices.size(); ++v) ASSERT_EQ(a.vertices[v], b.vertices[v]);
}

// The four-hole pretzel's tube is thin where its lobes turn (|grad| is large
// there), so it needs a finer grid than the others to keep its genus.
TEST(MarchingCubes, FourHolePretzelHasGenusFour) {
    const IndexedMesh m = marchingCubesMesh(compileField(R"({"type": "polynomial", "preset": "pretzel4"})"), 192);
    const MeshTopology t = analyzeTopology(m);
    EXPECT_EQ(t.eulerCharacteristic, -6);
    EXPECT_TRUE(t.watertight());
    EXPECT_TRUE(t.manifold());
}

// Decocube: tubes around six circles, one on each face of a cube, joined
// where neighbouring circles pass close (at the 12 edges): six handles plus
// 12 - 5 joining ones, genus 13, Euler characteristic -24 (the same at 96
// and 160 cells).
TEST(MarchingCubes, DecocubeHasGenusThirteen) {
    const MeshTopology t =
        analyzeTopology(marchingCubesMesh(compileField(R"({"type": "polynomial", "preset": "decocube"})"), 96));
    EXPECT_EQ(t.eulerCharacteristic, -24);
}

// Every closed field of every scene in scenes/ meshes watertight and 2-manifold.
TEST(MarchingCubes, EveryFieldOfEverySceneIsWatertightAndManifold) {
    int checked = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(ISOTRACE_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        const Json scene = parseJsonFile(entry.path().string());
        if (!scene.contains("fields")) continue;
        const FieldLibrary library(scene.at("fields"), "/fields", entry.path().string());
        for (const std::string& name : library.names()) {
            const FieldProgram field = library.compile(name);
            if (!field.bounds().isFinite()) continue;
            // primitives.json shows a hyperboloid cut open by its domain: not closed.
            if (entry.path().filename() == "primitives.json" && name == "quadric") continue;
            const MeshTopology t = analyzeTopology(marchingCubesMesh(field, 64));
            EXPECT_TRUE(t.watertight()) << entry.path().filename() << " " << name;
            EXPECT_TRUE(t.manifold()) << entry.path().filename() << " " << name;
            ++checked;
        }
    }
    EXPECT_GT(checked, 20);
}
