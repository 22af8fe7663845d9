#include "geometry/mesh_file.h"

#include <gtest/gtest.h>

#include "geometry/errors.h"

#include <set>
#include "support/temporary_files.h"

using namespace isotrace::geometry;
using isotrace::testing::TemporaryFolder;

namespace {

const char* kTetrahedron = "OFF\n4 4 0\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n";

std::string errorOf(const std::string& path) {
    try {
        readMeshFile(path);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(MeshFile, ReadsAnOffFile) {
    TemporaryFolder folder;
    const IndexedMesh m = readMeshFile(folder.write("tet.off", kTetrahedron));
    EXPECT_EQ(m.vertices.size(), 4u);
    ASSERT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.triangles[1], (std::array<uint32_t, 3>{0, 3, 1}));
    EXPECT_EQ(m.vertices[3], Vec3(-1, -1, 1));
}

// COFF (OFF with a colour per vertex, as Princeton's shape benchmark and
// many scanners write it) reads as the same mesh; the colours are dropped.
// Other headers are still refused, naming the line.
TEST(MeshFile, ReadsColouredOffAsTheSameMesh) {
    TemporaryFolder folder;
    const IndexedMesh plain = readMeshFile(folder.write("tet.off", kTetrahedron));
    const IndexedMesh coloured = readMeshFile(folder.write(
        "coloured.off", "COFF\n4 4 0\n1 1 1 255 0 0 255\n1 -1 -1 0 255 0 255\n-1 1 -1 0 0 255 255\n"
                        "-1 -1 1 9 9 9 255\n3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n"));
    EXPECT_EQ(coloured.vertices, plain.vertices);
    EXPECT_EQ(coloured.triangles, plain.triangles);
    const std::string error = errorOf(folder.write("other.off", "NOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_NE(error.find("line 1"), std::string::npos) << error;
    EXPECT_NE(error.find("expected \"OFF\" or \"COFF\""), std::string::npos) << error;
}

// Assimp clamps OFF indices into range; isotrace checks them first and
// names the line.
TEST(MeshFile, OffIndicesOutOfRangeNegativeOrMissingAreErrors) {
    TemporaryFolder folder;
    const std::string base = "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    EXPECT_NE(errorOf(folder.write("high.off", base + "3 0 2 99\n")).find("line 7: face 0 refers to vertex 99, but there are 4"),
              std::string::npos);
    EXPECT_NE(errorOf(folder.write("negative.off", base + "3 0 -1 2\n")).find("refers to vertex -1"), std::string::npos);
    EXPECT_NE(errorOf(folder.write("short.off", base + "3 0 1\n")).find("lists fewer than 3"), std::string::npos);
    EXPECT_NE(errorOf(folder.write("truncated.off", "OFF\n4 1 0\n0.0000 0.0000 0.0000\n1.0000 0.0000 0.0000\n")).find("ends after 2 of its 4 vertices"),
              std::string::npos);
    EXPECT_NE(errorOf(folder.write("nofaces.off", base)).find("ends after 0 of its 1 faces"), std::string::npos);
    EXPECT_NE(errorOf(folder.write("magic.off", "OF\n")).find("expected \"OFF\""), std::string::npos);
}

// A 100-byte file whose header claims a billion vertices fails at once,
// before anything is allocated for them.
TEST(MeshFile, CountsMustFitInTheFile) {
    TemporaryFolder folder;
    EXPECT_NE(errorOf(folder.write("huge.off", "OFF\n1000000000 1 0\n0 0 0\n")).find("more than the file's"),
              std::string::npos);
    const std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                            "end_header\n";
    EXPECT_NE(errorOf(folder.write("huge.ply", ply)).find("line 3: the header claims 1000000000 vertex elements"),
              std::string::npos);
}

// Assimp's PLY reader never returned from a header without "end_header"
// (a fuzzer's find: "end_head"); it must fail at once, naming the place.
TEST(MeshFile, PlyHeaderMustEnd) {
    TemporaryFolder folder;
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_head\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const std::string error = errorOf(folder.write("unended.ply", ply));
    EXPECT_NE(error.find("unended.ply"), std::string::npos) << error;
    EXPECT_NE(error.find("line 13: no \"end_header\" line by here"), std::string::npos) << error;
}

TEST(MeshFile, OnlyTheDocumentedFormats) {
    TemporaryFolder folder;
    EXPECT_NE(errorOf(folder.write("part.stl", "solid x\nendsolid x\n")).find("unknown mesh format \".stl\""),
              std::string::npos);
    EXPECT_NE(errorOf(folder.file("missing.off")).find("mesh file not found"), std::string::npos);
}

// A tetrahedron whose faces each have their own copies of the corners (as
// UV seams leave them), one copy off by less than the tolerance, plus a
// triangle that collapses: welding leaves the four corners and the four
// faces.
TEST(MeshFile, WeldingMergesCoincidentVerticesAndDropsDegenerateTriangles) {
    IndexedMesh m;
    const Vec3 corners[4] = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
    const std::array<uint32_t, 3> faces[4] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    for (const auto& f : faces) {
        const uint32_t base = uint32_t(m.vertices.size());
        for (uint32_t i : f) m.vertices.push_back(corners[i] + Vec3(1e-9 * base, 0, 0));
        m.triangles.push_back({base, base + 1, base + 2});
    }
    m.vertices.push_back(corners[0] + Vec3(0, 1e-3, 0));  // near, but not within the tolerance
    m.triangles.push_back({0, 3, uint32_t(m.vertices.size() - 1)});  // 0 and 3 weld: it collapses
    const MeshRepair repair = weldCoincidentVertices(m);
    EXPECT_EQ(repair.weldedVertices, 8u);
    EXPECT_EQ(repair.droppedTriangles, 1u);
    ASSERT_EQ(m.triangles.size(), 4u);
    std::set<uint32_t> used;
    for (const auto& t : m.triangles) used.insert(t.begin(), t.end());
    EXPECT_EQ(used.size(), 4u);
}
