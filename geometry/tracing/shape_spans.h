// Where a ray is inside a shape, in closed form or by exact polynomial
// roots, in the shape's own frame: the pieces shared by the cells of one
// shape (sphere_cells, box_cells, torus_cells) and the cells where several
// of them meet in a sharp CSG tree (csg_cells).
#pragma once

#include <vector>

#include "geometry/bernstein_root.h"
#include "geometry/bounding_box.h"
#include "geometry/fields/box.h"
#include "geometry/fields/sphere.h"
#include "geometry/fields/torus.h"

namespace isotrace::geometry {

/// The ray's parameters where it is inside the sphere (on the whole line);
/// false when it misses.
bool sphereSpan(const SphereField& sphere, const Vec3& o, const Vec3& d, double& enter, double& leave);

/// A rounded box as the union of three boxes (the core grown by the
/// rounding along one axis each), twelve cylinders along the core's edges
/// and eight balls at its corners (a sharp box: one box). The solid is
/// convex: a ray enters it where it first enters a piece and leaves where
/// it last leaves one.
class RoundedBoxPieces {
public:
    /// The pieces that reach `region` (in the box's frame): a cell on a
    /// flat face keeps one.
    RoundedBoxPieces(const BoxField& box, const Box3& region);
    bool empty() const { return pieces_.empty(); }
    /// The ray's span inside the solid within [t0, t1], from the kept
    /// pieces; false when empty. `o` and `d` in the box's frame.
    bool span(const Vec3& o, const Vec3& d, double t0, double t1, double& enter, double& leave) const;
    size_t pieceCount() const { return pieces_.size(); }

private:
    struct Piece {
        enum class Kind : uint8_t { Slab, Cylinder, Ball };
        Kind kind;
        int axis = 0;  ///< a cylinder's axis
        Vec3 centre;   ///< a ball's centre; a point on a cylinder's axis (box-centred)
        Box3 extent;   ///< a slab's box; a cylinder's or ball's bounding box (box-centred)
    };
    bool pieceSpan(const Piece& piece, const Vec3& local, const Vec3& d, double t0, double t1, double& enter,
                   double& leave) const;

    Vec3 centre_;
    double rounding_;
    std::vector<Piece> pieces_;
};

/// The torus's implicit quartic (|x - c|^2 + R^2 - r^2)^2 - 4 R^2 ((x - c)_x^2 +
/// (x - c)_z^2) along the ray, in s = t - tc where tc is the ray's closest
/// approach to the centre (small, well-conditioned monomials); negative
/// inside the torus.
Monomials<4> torusQuarticAlongRay(const TorusField& torus, const Vec3& o, const Vec3& d, double& tc);

}  // namespace isotrace::geometry
