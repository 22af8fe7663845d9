#include "triangle_mesh.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <filesystem>

#include "geometry/input_error.h"

namespace isotrace {

using geometry::InputError;

namespace {
bool isDegenerate(const TriangleMesh& m, size_t t) {
    const uint32_t a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2];
    if (a == b || b == c || a == c) return true;
    const Vec3 e1 = m.vertex(b) - m.vertex(a), e2 = m.vertex(c) - m.vertex(a);
    return !(e1.cross(e2).norm() > 0);
}
}  // namespace

long TriangleMesh::firstDegenerateTriangle() const {
    for (size_t t = 0; t < triangleCount(); ++t)
        if (isDegenerate(*this, t)) return static_cast<long>(t);
    return -1;
}

size_t TriangleMesh::dropDegenerateTriangles() {
    std::vector<uint32_t> kept;
    kept.reserve(indices.size());
    for (size_t t = 0; t < triangleCount(); ++t)
        if (!isDegenerate(*this, t)) kept.insert(kept.end(), indices.begin() + 3 * t, indices.begin() + 3 * t + 3);
    const size_t dropped = triangleCount() - kept.size() / 3;
    indices = std::move(kept);
    return dropped;
}

void TriangleMesh::computeSmoothNormals() {
    std::vector<Vec3> sum(vertexCount(), Vec3::Zero());
    for (size_t t = 0; t < triangleCount(); ++t) {
        const uint32_t a = indices[3 * t], b = indices[3 * t + 1], c = indices[3 * t + 2];
        // The cross product's length is twice the area: area weighting for free.
        const Vec3 n = (vertex(b) - vertex(a)).cross(vertex(c) - vertex(a));
        sum[a] += n;
        sum[b] += n;
        sum[c] += n;
    }
    normals.resize(positions.size());
    for (size_t v = 0; v < sum.size(); ++v) {
        const Vec3 n = sum[v].norm() > 0 ? Vec3(sum[v].normalized()) : Vec3(0, 1, 0);
        for (int k = 0; k < 3; ++k) normals[3 * v + k] = float(n[k]);
    }
}

TriangleMesh loadTriangleMesh(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "", "mesh file not found");
    Assimp::Importer importer;
    // No post-processing: Assimp's steps assert (abort) on some corrupt
    // files, and degenerate triangles are to be reported, not hidden.
    // Polygons are split into fans below.
    const aiScene* scene = importer.ReadFile(path, 0);
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
        throw InputError(path, "", std::string("cannot read mesh: ") + importer.GetErrorString());
    TriangleMesh mesh;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* am = scene->mMeshes[m];
        const uint32_t base = static_cast<uint32_t>(mesh.vertexCount());
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
            const aiVector3D& p = am->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw InputError(path, "vertex " + std::to_string(v), "vertex coordinate is not a finite number");
            mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
        }
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            const aiFace& face = am->mFaces[f];
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= am->mNumVertices)
                    throw InputError(path, "face " + std::to_string(f),
                                     "refers to vertex " + std::to_string(face.mIndices[k]) + " of " +
                                         std::to_string(am->mNumVertices));
            // Points and lines carry no surface; polygons become fans.
            for (unsigned k = 2; k < face.mNumIndices; ++k)
                mesh.indices.insert(mesh.indices.end(),
                                    {base + face.mIndices[0], base + face.mIndices[k - 1], base + face.mIndices[k]});
        }
    }
    if (mesh.triangleCount() == 0) throw InputError(path, "", "mesh has no triangles");
    return mesh;
}

}  // namespace isotrace
