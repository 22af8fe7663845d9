#include "renderer/mesh_export.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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
    // A failure names the file asked for, not the temporary one written first.
    try {
        writeMesh(folder.file("missing/t.ply"), mesh);
        ADD_FAILURE() << "no error for a missing folder";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("missing/t.ply"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find("partial"), std::string::npos) << e.what();
    }
}

// A field with no surface in its bounds polygonizes to an empty mesh: every
// format still writes a valid, empty file.
TEST(MeshExport, EmptyMeshesWriteEmptyFiles) {
    TemporaryFolder folder;
    const geometry::IndexedMesh empty;
    for (const char* name : {"e.ply", "e.obj", "e.off"}) {
        ASSERT_NO_THROW(writeMesh(folder.file(name), empty)) << name;
        EXPECT_TRUE(std::filesystem::exists(folder.file(name))) << name;
    }
    std::ifstream ply(folder.file("e.ply"));
    std::string header((std::istreambuf_iterator<char>(ply)), {});
    EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\nelement vertex 0\n", 0), 0u) << header;
    EXPECT_NE(header.find("element face 0\n"), std::string::npos) << header;
}
