// How far apart two surfaces are, and what a mesh's pieces are: the
// measures of a fit against the model it was fitted to. Distances go from
// points to the nearest point of a triangle mesh (or of a point set),
// through Embree's point queries; components are sets of triangles joined
// by shared vertices.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

/// The distance from any point to the nearest point of a fixed set of
/// triangles or, given no triangles, of points. Thread-safe queries.
class NearestSurface {
public:
    explicit NearestSurface(const IndexedMesh& mesh);
    ~NearestSurface();
    NearestSurface(const NearestSurface&) = delete;
    NearestSurface& operator=(const NearestSurface&) = delete;

    double distance(const Vec3& p) const;

private:
    struct Embree;
    std::unique_ptr<Embree> embree_;
    const IndexedMesh& mesh_;
};

struct DistanceSummary {
    double mean = 0.0, max = 0.0;
};

/// Distances from each of `points` to `surface`, summarized (in parallel).
DistanceSummary distancesTo(const NearestSurface& surface, const std::vector<Vec3>& points);

/// Closest point of triangle (a, b, c) to p.
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct MeshComponent {
    size_t triangles = 0;
    long long eulerCharacteristic = 0;  ///< V - E + F of the component
    bool closed = false;                ///< every edge has two triangles
    /// (2 - chi) / 2 for a closed component; -1 where it is not closed.
    long long genus() const { return closed ? (2 - eulerCharacteristic) / 2 : -1; }
};

/// The mesh's connected components (triangles sharing a vertex), largest first.
std::vector<MeshComponent> meshComponents(const IndexedMesh& mesh);

}  // namespace isotrace::geometry
