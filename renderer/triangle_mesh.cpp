#include "renderer/triangle_mesh.h"

#include <array>
#include <functional>
#include <unordered_map>

#include "geometry/errors.h"
#include "geometry/mesh_file.h"

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
    // Each vertex sums into the first vertex at its place.
    struct PlaceHash {
        size_t operator()(const std::array<float, 3>& p) const {
            return std::hash<float>()(p[0]) ^ (std::hash<float>()(p[1]) << 1) ^ (std::hash<float>()(p[2]) << 2);
        }
    };
    std::unordered_map<std::array<float, 3>, uint32_t, PlaceHash> firstAt;
    std::vector<uint32_t> place(vertexCount());
    for (uint32_t v = 0; v < vertexCount(); ++v)
        place[v] = firstAt.try_emplace({positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]}, v).first->second;
    std::vector<Vec3> sum(vertexCount(), Vec3::Zero());
    for (size_t t = 0; t < triangleCount(); ++t) {
        const uint32_t a = place[indices[3 * t]], b = place[indices[3 * t + 1]], c = place[indices[3 * t + 2]];
        // The cross product's length is twice the area: area weighting for free.
        const Vec3 n = (vertex(b) - vertex(a)).cross(vertex(c) - vertex(a));
        sum[a] += n;
        sum[b] += n;
        sum[c] += n;
    }
    normals.resize(positions.size());
    for (size_t v = 0; v < sum.size(); ++v) {
        const Vec3& s = sum[place[v]];
        const Vec3 n = s.norm() > 0 ? Vec3(s.normalized()) : Vec3(0, 1, 0);
        for (int k = 0; k < 3; ++k) normals[3 * v + k] = float(n[k]);
    }
}

TriangleMesh loadTriangleMesh(const std::string& path) {
    std::vector<std::array<float, 2>> uvs;
    const geometry::IndexedMesh read = geometry::readMeshFile(path, &uvs);
    TriangleMesh mesh;
    mesh.uvs.reserve(2 * uvs.size());
    for (const auto& uv : uvs) mesh.uvs.insert(mesh.uvs.end(), {uv[0], uv[1]});
    mesh.positions.reserve(3 * read.vertices.size());
    for (const Vec3& v : read.vertices) mesh.positions.insert(mesh.positions.end(), {float(v.x()), float(v.y()), float(v.z())});
    mesh.indices.reserve(3 * read.triangles.size());
    for (const auto& t : read.triangles) mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
    return mesh;
}

}  // namespace isotrace
