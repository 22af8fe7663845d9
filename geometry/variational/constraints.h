// What a variational implicit surface interpolates (Turk and O'Brien 1999,
// 2002): values at points (0 on the surface, negative inside, positive
// outside) and, optionally, exact gradients (Hermite interpolation, which
// the papers name as future work).
#pragma once

#include <string>
#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

struct ValueConstraint {
    Vec3 position;
    double value = 0.0;
};

struct GradientConstraint {
    Vec3 position;
    Vec3 gradient;
};

struct ConstraintSet {
    std::vector<ValueConstraint> values;
    std::vector<GradientConstraint> gradients;

    void addBoundary(const Vec3& p) { values.push_back({p, 0.0}); }
    /// The papers' interior and exterior constraints carry magnitude 1.
    void addInterior(const Vec3& p, double value = -1.0) { values.push_back({p, value}); }
    void addExterior(const Vec3& p, double value = 1.0) { values.push_back({p, value}); }
    /// A boundary constraint at p and an exterior one `offset` along the
    /// outward normal n with value `offset`, so the field grows like a
    /// distance across the surface.
    void addNormal(const Vec3& p, const Vec3& n, double offset) {
        addBoundary(p);
        values.push_back({p + offset * n.normalized(), offset});
    }
    /// A boundary constraint and the exact gradient n (unit) at p.
    void addHermite(const Vec3& p, const Vec3& n) {
        addBoundary(p);
        gradients.push_back({p, n.normalized()});
    }
    size_t unknowns() const { return values.size() + 3 * gradients.size() + 4; }
    Box3 bounds() const;
};

struct OrientedPoint {
    Vec3 position;
    Vec3 normal;  ///< outward, unit
};

/// An oriented point set: "x y z nx ny nz" per line ('#' starts a comment)
/// in a .xyz, .pwn or .pts file. Malformed lines, non-finite or zero normals
/// throw InputError naming the file and line; so do sets that cannot
/// outline a solid (checkPointsOutlineASolid) and sets of fewer than
/// kMinimumOrientedPoints.
std::vector<OrientedPoint> readOrientedPoints(const std::string& path);

/// Whether `path` names an oriented point set by its extension (.xyz, .pwn or
/// .pts, any case) rather than a polygon model.
bool isOrientedPointFile(const std::string& path);

/// Fewer loose oriented points than this cannot outline a surface worth
/// fitting (a mesh may have fewer vertices: its faces say what is inside).
inline constexpr size_t kMinimumOrientedPoints = 6;

/// Throws InputError naming `file` when the points all lie in one plane (or
/// on a line, or at one place).
void checkPointsOutlineASolid(const std::vector<OrientedPoint>& points, const std::string& file);

/// The vertices of a polygon model with their area-weighted normals.
std::vector<OrientedPoint> orientedPointsOfMesh(const IndexedMesh& mesh);

/// The papers' default normal-constraint offset: 0.01 of the bounding-box
/// diagonal of the points.
double defaultNormalOffset(const std::vector<OrientedPoint>& points);

/// Boundary plus normal constraints for each point (or boundary plus
/// gradient constraints when `hermite`).
ConstraintSet constraintsFromOrientedPoints(const std::vector<OrientedPoint>& points, double normalOffset, bool hermite);

}  // namespace isotrace::geometry
