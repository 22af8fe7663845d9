#include "renderer/mesh_export.h"

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include "geometry/mesh_file.h"

namespace isotrace {

namespace {

void writeOff(const std::string& path, const geometry::IndexedMesh& mesh) {
    std::ofstream out(path);
    out.precision(9);
    out << "OFF\n" << mesh.vertices.size() << ' ' << mesh.triangles.size() << " 0\n";
    for (const auto& v : mesh.vertices) out << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    if (!out.flush()) throw std::runtime_error(path + ": cannot write the mesh");
}

void writeWithAssimp(const std::string& path, const geometry::IndexedMesh& mesh, const char* formatId) {
    // A one-mesh scene; Assimp owns and frees what is attached to it.
    aiScene scene;
    scene.mRootNode = new aiNode();
    scene.mMaterials = new aiMaterial*[1]{new aiMaterial()};
    scene.mNumMaterials = 1;
    scene.mMeshes = new aiMesh*[1]{new aiMesh()};
    scene.mNumMeshes = 1;
    scene.mRootNode->mMeshes = new unsigned[1]{0};
    scene.mRootNode->mNumMeshes = 1;
    aiMesh* m = scene.mMeshes[0];
    m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    m->mNumVertices = static_cast<unsigned>(mesh.vertices.size());
    m->mVertices = new aiVector3D[m->mNumVertices];
    if (!mesh.normals.empty()) m->mNormals = new aiVector3D[m->mNumVertices];
    for (unsigned i = 0; i < m->mNumVertices; ++i) {
        const auto& v = mesh.vertices[i];
        m->mVertices[i] = aiVector3D(float(v.x()), float(v.y()), float(v.z()));
        if (m->mNormals) {
            const auto& n = mesh.normals[i];
            m->mNormals[i] = aiVector3D(float(n.x()), float(n.y()), float(n.z()));
        }
    }
    m->mNumFaces = static_cast<unsigned>(mesh.triangles.size());
    m->mFaces = new aiFace[m->mNumFaces];
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
        m->mFaces[f].mNumIndices = 3;
        m->mFaces[f].mIndices = new unsigned[3]{mesh.triangles[f][0], mesh.triangles[f][1], mesh.triangles[f][2]};
    }
    Assimp::Exporter exporter;
    if (exporter.Export(&scene, formatId, path) != AI_SUCCESS)
        throw std::runtime_error(path + ": cannot write the mesh: " + exporter.GetErrorString());
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
        else writeWithAssimp(temporary, mesh, e == ".ply" ? "plyb" : "objnomtl");
        std::filesystem::rename(temporary, path);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw;
    }
}

}  // namespace isotrace
