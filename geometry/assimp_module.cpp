// The Assimp module (isotrace_assimp.so): the one place that includes
// Assimp. It moves data between Assimp's scenes and plain arrays; checking
// what was read is left to the caller (mesh_file.cpp), which names the
// file and the place in it.
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <stdexcept>

#include "geometry/assimp_library.h"

namespace isotrace::geometry {

namespace {

class Library final : public AssimpLibrary {
public:
    MeshFileContents read(const std::string& path) override {
        Assimp::Importer importer;
        // No post-processing: Assimp's steps assert (abort) on some corrupt
        // files, and degenerate triangles are for the caller to report, not hide.
        const aiScene* scene = importer.ReadFile(path, 0);
        if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
            throw std::runtime_error(importer.GetErrorString());
        MeshFileContents contents;
        contents.parts.resize(scene->mNumMeshes);
        for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
            const aiMesh* am = scene->mMeshes[m];
            MeshFileContents::Part& part = contents.parts[m];
            part.vertices.reserve(am->mNumVertices);
            for (unsigned v = 0; v < am->mNumVertices; ++v) {
                const aiVector3D& p = am->mVertices[v];
                part.vertices.emplace_back(p.x, p.y, p.z);
            }
            if (const aiVector3D* uv = am->mTextureCoords[0]) {
                part.uvs.reserve(am->mNumVertices);
                for (unsigned v = 0; v < am->mNumVertices; ++v) part.uvs.push_back({uv[v].x, uv[v].y});
            }
            part.faceSizes.reserve(am->mNumFaces);
            for (unsigned f = 0; f < am->mNumFaces; ++f) {
                const aiFace& face = am->mFaces[f];
                part.faceSizes.push_back(face.mNumIndices);
                part.indices.insert(part.indices.end(), face.mIndices, face.mIndices + face.mNumIndices);
            }
        }
        return contents;
    }

    void write(const std::string& path, const IndexedMesh& mesh, const std::string& formatId) override {
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
            const Vec3& v = mesh.vertices[i];
            m->mVertices[i] = aiVector3D(float(v.x()), float(v.y()), float(v.z()));
            if (m->mNormals) {
                const Vec3& n = mesh.normals[i];
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
        if (exporter.Export(&scene, formatId.c_str(), path) != AI_SUCCESS)
            throw std::runtime_error(exporter.GetErrorString());
    }
};

}  // namespace

}  // namespace isotrace::geometry

extern "C" __attribute__((visibility("default"))) isotrace::geometry::AssimpLibrary* isotraceAssimpLibrary() {
    static isotrace::geometry::Library library;
    return &library;
}
