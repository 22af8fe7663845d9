// Distances to meshes and point sets against brute force, and components
// with their genus against closed surfaces of known topology.
#include "geometry/meshing/mesh_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

using namespace isotrace::geometry;

namespace {

IndexedMesh torus(double major, double minor, const Vec3& center, int n = 24, int m = 12) {
    IndexedMesh mesh;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
            mesh.vertices.push_back(center + Vec3((major + minor * std::cos(v)) * std::cos(u), minor * std::sin(v),
                                                  (major + minor * std::cos(v)) * std::sin(u)));
        }
    auto at = [&](int i, int j) { return uint32_t(((i + n) % n) * m + (j + m) % m); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    return mesh;
}

}  // namespace

TEST(MeshDistance, NearestPointsMatchBruteForce) {
    const IndexedMesh mesh = torus(1.0, 0.3, Vec3(0.1, 0.2, -0.1));
    IndexedMesh points;
    points.vertices = mesh.vertices;  // the same vertices, as a point set
    const NearestSurface toMesh(mesh), toPoints(points);
    std::mt19937 random(3);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int trial = 0; trial < 300; ++trial) {
        const Vec3 p(u(random), u(random), u(random));
        double triangles = std::numeric_limits<double>::infinity(), vertices = triangles;
        for (const auto& t : mesh.triangles)
            triangles = std::min(triangles, (closestPointOnTriangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                                    mesh.vertices[t[2]]) - p).norm());
        for (const Vec3& v : mesh.vertices) vertices = std::min(vertices, (v - p).norm());
        EXPECT_NEAR(toMesh.distance(p), triangles, 1e-6) << p.transpose();
        EXPECT_NEAR(toPoints.distance(p), vertices, 1e-6) << p.transpose();
        EXPECT_LE(triangles, vertices + 1e-12);
    }
    const DistanceSummary onItself = distancesTo(toMesh, mesh.vertices);
    EXPECT_LT(onItself.max, 1e-6);
}

TEST(MeshDistance, ClosestPointOnATriangleInEveryRegion) {
    const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
    EXPECT_TRUE(closestPointOnTriangle(Vec3(0.5, 0.5, 3), a, b, c).isApprox(Vec3(0.5, 0.5, 0)));  // the face
    EXPECT_TRUE(closestPointOnTriangle(Vec3(-1, -1, 1), a, b, c).isApprox(a));                       // a vertex
    EXPECT_TRUE(closestPointOnTriangle(Vec3(1, -1, 0), a, b, c).isApprox(Vec3(1, 0, 0)));           // an edge
    EXPECT_TRUE(closestPointOnTriangle(Vec3(2, 2, 0), a, b, c).isApprox(Vec3(1, 1, 0)));            // the long edge
}

TEST(MeshDistance, ComponentsAndTheirGenus) {
    IndexedMesh two = torus(1.0, 0.3, Vec3::Zero());
    const IndexedMesh other = torus(0.5, 0.1, Vec3(5, 0, 0), 16, 8);
    const uint32_t base = uint32_t(two.vertices.size());
    two.vertices.insert(two.vertices.end(), other.vertices.begin(), other.vertices.end());
    for (auto t : other.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    // A lone open triangle: a third component, not closed.
    two.vertices.insert(two.vertices.end(), {Vec3(9, 0, 0), Vec3(10, 0, 0), Vec3(9, 1, 0)});
    two.triangles.push_back({base + uint32_t(other.vertices.size()), base + uint32_t(other.vertices.size()) + 1,
                             base + uint32_t(other.vertices.size()) + 2});
    const std::vector<MeshComponent> components = meshComponents(two);
    ASSERT_EQ(components.size(), 3u);
    EXPECT_EQ(components[0].triangles, 24u * 12 * 2);
    EXPECT_TRUE(components[0].closed);
    EXPECT_EQ(components[0].genus(), 1);
    EXPECT_EQ(components[1].genus(), 1);
    EXPECT_FALSE(components[2].closed);
    EXPECT_EQ(components[2].genus(), -1);
}
