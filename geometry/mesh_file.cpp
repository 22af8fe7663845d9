#include "geometry/mesh_file.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <cmath>
#include <filesystem>

#include "geometry/input_error.h"

namespace isotrace::geometry {

IndexedMesh readMeshFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "", "mesh file not found");
    Assimp::Importer importer;
    // No post-processing: Assimp's steps assert (abort) on some corrupt
    // files, and degenerate triangles are for the caller to report, not hide.
    const aiScene* scene = importer.ReadFile(path, 0);
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
        throw InputError(path, "", std::string("cannot read mesh: ") + importer.GetErrorString());
    IndexedMesh mesh;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* am = scene->mMeshes[m];
        const uint32_t base = static_cast<uint32_t>(mesh.vertices.size());
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
            const aiVector3D& p = am->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw InputError(path, "vertex " + std::to_string(v), "vertex coordinate is not a finite number");
            mesh.vertices.emplace_back(p.x, p.y, p.z);
        }
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            const aiFace& face = am->mFaces[f];
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= am->mNumVertices)
                    throw InputError(path, "face " + std::to_string(f),
                                     "refers to vertex " + std::to_string(face.mIndices[k]) + " of " +
                                         std::to_string(am->mNumVertices));
            for (unsigned k = 2; k < face.mNumIndices; ++k)
                mesh.triangles.push_back(
                    {base + face.mIndices[0], base + face.mIndices[k - 1], base + face.mIndices[k]});
        }
    }
    if (mesh.triangles.empty()) throw InputError(path, "", "mesh has no triangles");
    return mesh;
}

std::vector<Vec3> areaWeightedVertexNormals(const IndexedMesh& mesh) {
    std::vector<Vec3> sum(mesh.vertices.size(), Vec3::Zero());
    for (const auto& t : mesh.triangles) {
        // The cross product's length is twice the area: area weighting for free.
        const Vec3 n = (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
        for (uint32_t v : t) sum[v] += n;
    }
    for (Vec3& n : sum) n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(0, 1, 0);
    return sum;
}

}  // namespace isotrace::geometry
