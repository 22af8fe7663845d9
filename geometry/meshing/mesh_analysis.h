// What a polygonization is worth: its topology (watertight, manifold, Euler
// characteristic) and how closely it follows the field it came from.
#pragma once

#include <cmath>
#include <cstddef>

#include "geometry/field_program.h"
#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

struct MeshTopology {
    size_t vertices = 0;  ///< vertices used by some triangle
    size_t edges = 0;
    size_t triangles = 0;
    size_t boundaryEdges = 0;        ///< edges of one triangle
    size_t nonManifoldEdges = 0;     ///< edges of three or more triangles
    size_t nonManifoldVertices = 0;  ///< vertices whose triangles form more than one fan
    size_t inconsistentEdges = 0;    ///< edges both of whose triangles run the same way along them
    long long eulerCharacteristic = 0;  ///< V - E + F

    bool watertight() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
    bool manifold() const { return nonManifoldEdges == 0 && nonManifoldVertices == 0; }
    bool oriented() const { return inconsistentEdges == 0; }
};

MeshTopology analyzeTopology(const IndexedMesh& mesh);

struct MeshAccuracy {
    /// First-order distance to the surface, |f| / |grad f|.
    double maxVertexDistance = 0, meanVertexDistance = 0;
    double maxCentroidDistance = 0, meanCentroidDistance = 0;
    /// Angle between each face's normal and the field's gradient at its centroid.
    double maxNormalDeviationDegrees = 0, meanNormalDeviationDegrees = 0;
    /// Longest edge over the shortest altitude, times sqrt(3)/2 (1 for
    /// equilateral): the worst triangle's, and the value 99% of triangles
    /// are no worse than (a few slivers against a poor mesh throughout).
    double worstAspectRatio = 0, aspectRatio99thPercentile = 0;
};

MeshAccuracy measureAccuracy(const IndexedMesh& mesh, const FieldProgram& field);

/// The first-order distance of p to the field's surface, |f| / |grad f| (|f|
/// where the gradient vanishes): the measure every meshing tolerance is
/// held to. The gradient's length too, when asked for.
inline double surfaceDistance(const FieldProgram& field, const Vec3& p, double* gradientNorm = nullptr) {
    Vec3 g;
    const double f = field.valueAndGradient(p, g);
    const double n = g.norm();
    if (gradientNorm) *gradientNorm = n;
    return n > 0 ? std::abs(f) / n : std::abs(f);
}

/// The unit normal a mesh vertex takes from the field's gradient there
/// (+y where the gradient vanishes).
inline Vec3 vertexNormal(const Vec3& gradient) {
    return gradient.norm() > 0 ? Vec3(gradient.normalized()) : Vec3(0, 1, 0);
}

/// A triangle's longest edge over its shortest altitude, times sqrt(3)/2
/// (1 for equilateral, infinite for a degenerate triangle).
double triangleAspectRatio(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace isotrace::geometry
