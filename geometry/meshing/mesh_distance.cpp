#include "geometry/meshing/mesh_distance.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace isotrace::geometry {

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Voronoi regions of the vertices, then the edges, then the face
    // (Ericson, Real-Time Collision Detection, 5.1.5).
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    const double denominator = va + vb + vc;
    if (!(denominator > 0)) return a;  // a degenerate triangle: its first vertex
    return a + (vb / denominator) * ab + (vc / denominator) * ac;
}

struct NearestSurface::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

struct Query {
    const IndexedMesh* mesh;
    Vec3 p;
    double best;
};

bool nearestPrimitive(RTCPointQueryFunctionArguments* args) {
    Query& q = *static_cast<Query*>(args->userPtr);
    const IndexedMesh& mesh = *q.mesh;
    Vec3 nearest;
    if (mesh.triangles.empty()) {
        nearest = mesh.vertices[args->primID];
    } else {
        const auto& t = mesh.triangles[args->primID];
        nearest = closestPointOnTriangle(q.p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    }
    const double d = (nearest - q.p).norm();
    if (!(d < q.best)) return false;
    q.best = d;
    args->query->radius = float(d) * (1.0f + 1e-6f) + 1e-30f;  // single precision: never prune the true nearest
    return true;
}

}  // namespace

NearestSurface::NearestSurface(const IndexedMesh& mesh) : embree_(std::make_unique<Embree>()), mesh_(mesh) {
    if (mesh.vertices.empty()) throw std::invalid_argument("a surface to measure distances to needs points");
    embree_->device = rtcNewDevice(nullptr);
    embree_->scene = rtcNewScene(embree_->device);
    RTCGeometry geometry;
    if (mesh.triangles.empty()) {
        // A point set: user primitives whose bounds are their points (point
        // queries need nothing else; no ray is traced against them).
        geometry = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geometry, unsigned(mesh.vertices.size()));
        rtcSetGeometryUserData(geometry, const_cast<IndexedMesh*>(&mesh));
        rtcSetGeometryBoundsFunction(
            geometry,
            [](const RTCBoundsFunctionArguments* args) {
                const Vec3& p = static_cast<const IndexedMesh*>(args->geometryUserPtr)->vertices[args->primID];
                // Widened by a float's step, so that single precision keeps the point inside.
                const float lower[3] = {std::nextafter(float(p.x()), -INFINITY), std::nextafter(float(p.y()), -INFINITY),
                                        std::nextafter(float(p.z()), -INFINITY)};
                const float upper[3] = {std::nextafter(float(p.x()), INFINITY), std::nextafter(float(p.y()), INFINITY),
                                        std::nextafter(float(p.z()), INFINITY)};
                args->bounds_o->lower_x = lower[0], args->bounds_o->lower_y = lower[1], args->bounds_o->lower_z = lower[2];
                args->bounds_o->upper_x = upper[0], args->bounds_o->upper_y = upper[1], args->bounds_o->upper_z = upper[2];
            },
            nullptr);
    } else {
        geometry = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                     3 * sizeof(float), mesh.vertices.size()));
        for (size_t i = 0; i < mesh.vertices.size(); ++i)
            for (int k = 0; k < 3; ++k) vertices[3 * i + k] = float(mesh.vertices[i][k]);
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(unsigned), mesh.triangles.size()));
        for (size_t i = 0; i < mesh.triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) indices[3 * i + k] = mesh.triangles[i][k];
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(embree_->scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(embree_->scene);
}

NearestSurface::~NearestSurface() = default;

double NearestSurface::distance(const Vec3& p) const {
    Query q{&mesh_, p, std::numeric_limits<double>::infinity()};
    RTCPointQuery query;
    query.x = float(p.x());
    query.y = float(p.y());
    query.z = float(p.z());
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(embree_->scene, &query, &context, nearestPrimitive, &q);
    return q.best;
}

DistanceSummary distancesTo(const NearestSurface& surface, const std::vector<Vec3>& points) {
    if (points.empty()) return {};
    using Partial = std::pair<double, double>;  // sum, max
    const Partial total = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, points.size(), 256), Partial{0.0, 0.0},
        [&](const tbb::blocked_range<size_t>& range, Partial partial) {
            for (size_t i = range.begin(); i != range.end(); ++i) {
                const double d = surface.distance(points[i]);
                partial.first += d;
                partial.second = std::max(partial.second, d);
            }
            return partial;
        },
        [](const Partial& a, const Partial& b) { return Partial{a.first + b.first, std::max(a.second, b.second)}; });
    return {total.first / double(points.size()), total.second};
}

std::vector<MeshComponent> meshComponents(const IndexedMesh& mesh) {
    // Union-find over vertices; a triangle joins its three.
    std::vector<uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const auto& t : mesh.triangles) {
        const uint32_t a = find(t[0]);
        parent[find(t[1])] = a;
        parent[find(t[2])] = a;
    }
    std::map<uint32_t, size_t> componentOf;
    std::vector<MeshComponent> components;
    std::vector<std::map<std::pair<uint32_t, uint32_t>, int>> edges;
    std::vector<std::vector<uint32_t>> vertices;
    for (const auto& t : mesh.triangles) {
        const auto [it, added] = componentOf.try_emplace(find(t[0]), components.size());
        if (added) {
            components.emplace_back();
            edges.emplace_back();
            vertices.emplace_back();
        }
        const size_t c = it->second;
        ++components[c].triangles;
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], b = t[(k + 1) % 3];
            ++edges[c][{std::min(a, b), std::max(a, b)}];
            vertices[c].push_back(a);
        }
    }
    for (size_t c = 0; c < components.size(); ++c) {
        std::sort(vertices[c].begin(), vertices[c].end());
        const auto used = size_t(std::unique(vertices[c].begin(), vertices[c].end()) - vertices[c].begin());
        components[c].closed = std::all_of(edges[c].begin(), edges[c].end(), [](const auto& e) { return e.second == 2; });
        components[c].eulerCharacteristic =
            (long long)used - (long long)edges[c].size() + (long long)components[c].triangles;
    }
    std::sort(components.begin(), components.end(),
              [](const MeshComponent& a, const MeshComponent& b) { return a.triangles > b.triangles; });
    return components;
}

}  // namespace isotrace::geometry
