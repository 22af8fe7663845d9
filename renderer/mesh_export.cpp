#include "renderer/mesh_export.h"
#include "geometry/errors.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include "geometry/assimp_library.h"
#include "geometry/mesh_file.h"

namespace isotrace {

namespace {

void writeOff(const std::string& path, const geometry::IndexedMesh& mesh) {
    std::ofstream out(path);
    out.precision(9);
    out << "OFF\n" << mesh.vertices.size() << ' ' << mesh.triangles.size() << " 0\n";
    for (const auto& v : mesh.vertices) out << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    if (!out.flush()) throw geometry::IoError(path, "cannot write the mesh");
}

// Assimp's own message after the user's path (not the temporary one it
// writes), as the other write errors read.
void writeMeshWithAssimp(const std::string& temporary, const std::string& path, const geometry::IndexedMesh& mesh,
                         const char* formatId) {
    geometry::AssimpLibrary& assimp = geometry::assimpLibrary();
    try {
        assimp.write(temporary, mesh, formatId);
    } catch (const std::runtime_error& e) {
        std::string message = e.what();
        for (size_t at = message.find(temporary); at != std::string::npos; at = message.find(temporary, at + path.size()))
            message.replace(at, temporary.size(), path);
        throw geometry::IoError(path, "cannot write the mesh: " + message);
    }
}

// Assimp writes no PLY without faces; an empty mesh is still a valid file.
void writeEmptyPly(const std::string& temporary, const std::string& path) {
    std::ofstream out(temporary, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
           "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
    if (!out.flush()) throw geometry::IoError(path, "cannot write the mesh");
}

}  // namespace

bool isMeshExtension(const std::string& path) {
    const std::string e = geometry::lowercaseExtension(path);
    return e == ".ply" || e == ".obj" || e == ".off";
}

void writeMesh(const std::string& path, const geometry::IndexedMesh& mesh) {
    const std::string e = geometry::lowercaseExtension(path);
    if (!isMeshExtension(path)) throw std::runtime_error(path + ": unknown mesh format (use .ply, .obj or .off)");
    const std::filesystem::path p(path);
    const std::string temporary =
        (p.parent_path() / ("." + p.stem().string() + ".partial-" + std::to_string(getpid()) + e)).string();
    try {
        if (e == ".off") writeOff(temporary, mesh);
        else if (e == ".ply" && mesh.triangles.empty()) writeEmptyPly(temporary, path);
        else writeMeshWithAssimp(temporary, path, mesh, e == ".ply" ? "plyb" : "objnomtl");
        std::filesystem::rename(temporary, path);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

}  // namespace isotrace
