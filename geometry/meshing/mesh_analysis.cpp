#include "geometry/meshing/mesh_analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <unordered_map>

namespace isotrace::geometry {

namespace {
uint64_t undirected(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

int findRoot(std::vector<int>& parent, int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}
}  // namespace

MeshTopology analyzeTopology(const IndexedMesh& mesh) {
    MeshTopology t;
    t.triangles = mesh.triangles.size();
    // Per undirected edge: how many triangles, and the sum of directions.
    struct EdgeUse {
        int count = 0;
        int forward = 0;  ///< triangles running min -> max along it
    };
    std::unordered_map<uint64_t, EdgeUse> edges;
    std::vector<std::vector<uint32_t>> trianglesOfVertex(mesh.vertices.size());
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const auto& tri = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            EdgeUse& e = edges[undirected(a, b)];
            ++e.count;
            if (a < b) ++e.forward;
            trianglesOfVertex[a].push_back(f);
        }
    }
    t.edges = edges.size();
    for (const auto& [key, use] : edges) {
        if (use.count == 1) ++t.boundaryEdges;
        if (use.count > 2) ++t.nonManifoldEdges;
        if (use.count == 2 && use.forward != 1) ++t.inconsistentEdges;
    }
    // A manifold vertex's triangles form one fan: connected through the
    // edges that contain the vertex.
    for (uint32_t v = 0; v < mesh.vertices.size(); ++v) {
        const auto& around = trianglesOfVertex[v];
        if (around.empty()) continue;
        ++t.vertices;
        std::vector<int> parent(around.size());
        std::iota(parent.begin(), parent.end(), 0);
        std::map<uint32_t, int> firstWithNeighbour;
        for (size_t i = 0; i < around.size(); ++i) {
            for (uint32_t w : mesh.triangles[around[i]]) {
                if (w == v) continue;
                const auto [it, inserted] = firstWithNeighbour.emplace(w, int(i));
                if (!inserted) parent[findRoot(parent, int(i))] = findRoot(parent, it->second);
            }
        }
        int roots = 0;
        for (size_t i = 0; i < around.size(); ++i)
            if (findRoot(parent, int(i)) == int(i)) ++roots;
        if (roots > 1) ++t.nonManifoldVertices;
    }
    t.eulerCharacteristic = (long long)t.vertices - (long long)t.edges + (long long)t.triangles;
    return t;
}

double triangleAspectRatio(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double area2 = (b - a).cross(c - a).norm();
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    return area2 > 0 ? longest / area2 * (std::sqrt(3.0) / 2.0) : std::numeric_limits<double>::infinity();
}

MeshAccuracy measureAccuracy(const IndexedMesh& mesh, const FieldProgram& field) {
    MeshAccuracy a;
    auto distance = [&](const Vec3& p) { return surfaceDistance(field, p); };
    size_t used = 0;
    std::vector<bool> isUsed(mesh.vertices.size(), false);
    for (const auto& tri : mesh.triangles)
        for (uint32_t v : tri) isUsed[v] = true;
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!isUsed[v]) continue;
        const double d = distance(mesh.vertices[v]);
        a.maxVertexDistance = std::max(a.maxVertexDistance, d);
        a.meanVertexDistance += d;
        ++used;
    }
    if (used) a.meanVertexDistance /= double(used);
    std::vector<double> aspects;
    aspects.reserve(mesh.triangles.size());
    for (const auto& tri : mesh.triangles) {
        const Vec3 &p0 = mesh.vertices[tri[0]], &p1 = mesh.vertices[tri[1]], &p2 = mesh.vertices[tri[2]];
        const Vec3 centroid = (p0 + p1 + p2) / 3.0;
        const double d = distance(centroid);
        a.maxCentroidDistance = std::max(a.maxCentroidDistance, d);
        a.meanCentroidDistance += d;
        const Vec3 n = (p1 - p0).cross(p2 - p0);
        Vec3 g;
        field.valueAndGradient(centroid, g);
        if (n.norm() > 0 && g.norm() > 0) {
            const double angle =
                std::acos(std::clamp(n.normalized().dot(g.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
            a.maxNormalDeviationDegrees = std::max(a.maxNormalDeviationDegrees, angle);
            a.meanNormalDeviationDegrees += angle;
        }
        const double aspect = triangleAspectRatio(p0, p1, p2);
        a.worstAspectRatio = std::max(a.worstAspectRatio, aspect);
        aspects.push_back(aspect);
    }
    if (!aspects.empty()) {
        const auto at = aspects.begin() + std::ptrdiff_t(std::ceil(0.99 * double(aspects.size())) - 1);
        std::nth_element(aspects.begin(), at, aspects.end());
        a.aspectRatio99thPercentile = *at;
    }
    if (!mesh.triangles.empty()) {
        a.meanCentroidDistance /= double(mesh.triangles.size());
        a.meanNormalDeviationDegrees /= double(mesh.triangles.size());
    }
    return a;
}

}  // namespace isotrace::geometry
