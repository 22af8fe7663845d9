#include "renderer/mesh_export.h"

#include <gtest/gtest.h>

#include "geometry/description/field_parser.h"
#include "geometry/meshing/polygonizer.h"
#include "renderer/triangle_mesh.h"
#include "support/temporary_files.h"

using namespace isotrace;
using isotrace::testing::TemporaryFolder;

// Every format reads back (through Assimp) with the same counts.
TEST(MeshExport, EveryFormatRoundTrips) {
    const auto field = geometry::FieldLibrary(geometry::Json::object(), "", "test")
                           .compileDescription(geometry::Json::parse(R"({"type": "torus", "major": 1, "minor": 0.3})"), "");
    geometry::PolygonizeOptions options;
    options.resolution = 24;
    const geometry::IndexedMesh mesh = geometry::polygonize(field, options).mesh;
    TemporaryFolder folder;
    for (const char* name : {"t.ply", "t.obj", "t.off"}) {
        writeMesh(folder.file(name), mesh);
        const TriangleMesh back = loadTriangleMesh(folder.file(name));
        EXPECT_EQ(back.triangleCount(), mesh.triangles.size()) << name;
        // OBJ may duplicate vertices per face attribute; never lose any.
        EXPECT_GE(back.vertexCount(), mesh.vertices.size()) << name;
        EXPECT_NEAR(back.vertex(back.indices[0]).norm(), mesh.vertices[mesh.triangles[0][0]].norm(), 1e-5) << name;
    }
    EXPECT_THROW(writeMesh(folder.file("t.stl"), mesh), std::runtime_error);
    EXPECT_THROW(writeMesh(folder.file("missing/t.ply"), mesh), std::exception);
}
