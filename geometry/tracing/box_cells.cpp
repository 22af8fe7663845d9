#include "geometry/tracing/box_cells.h"

#include <cmath>
#include <vector>

#include "geometry/fields/box.h"
#include "geometry/quadratic_roots.h"

namespace isotrace::geometry {

namespace {

// One piece of a rounded box, in the box's own frame (centre at 0).
struct BoxPiece {
    enum class Kind : uint8_t { Slab, Cylinder, Ball };
    Kind kind;
    int axis = 0;  ///< a cylinder's axis
    Vec3 centre;   ///< a ball's centre; a point on a cylinder's axis
    Box3 extent;   ///< a slab's box; a cylinder's or ball's bounding box
};

std::vector<BoxPiece> piecesOf(const BoxField& box) {
    const double r = box.rounding;
    const Vec3 core = (box.halfSize - Vec3::Constant(r)).cwiseMax(0.0);
    std::vector<BoxPiece> pieces;
    if (!(r > 0)) {
        pieces.push_back({BoxPiece::Kind::Slab, 0, Vec3::Zero(), {-core, core}});
        return pieces;
    }
    for (int axis = 0; axis < 3; ++axis) {
        Vec3 half = core;
        half[axis] += r;
        pieces.push_back({BoxPiece::Kind::Slab, axis, Vec3::Zero(), {-half, half}});
    }
    for (int axis = 0; axis < 3; ++axis) {
        const int i = (axis + 1) % 3, j = (axis + 2) % 3;
        for (double si : {-1.0, 1.0})
            for (double sj : {-1.0, 1.0}) {
                Vec3 c = Vec3::Zero();
                c[i] = si * core[i];
                c[j] = sj * core[j];
                Vec3 lo = c - Vec3::Constant(r), hi = c + Vec3::Constant(r);
                lo[axis] = -core[axis];
                hi[axis] = core[axis];
                pieces.push_back({BoxPiece::Kind::Cylinder, axis, c, {lo, hi}});
            }
    }
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0})
            for (double sz : {-1.0, 1.0}) {
                const Vec3 c(sx * core.x(), sy * core.y(), sz * core.z());
                pieces.push_back({BoxPiece::Kind::Ball, 0, c, {c - Vec3::Constant(r), c + Vec3::Constant(r)}});
            }
    return pieces;
}

// The ray's interval inside one piece, within [t0, t1]; false when empty.
bool pieceInterval(const BoxPiece& piece, double r, const Vec3& o, const Vec3& d, double t0, double t1, double& enter,
                   double& leave) {
    enter = t0, leave = t1;
    switch (piece.kind) {
        case BoxPiece::Kind::Slab:
            return clipRayToBox(piece.extent, o, d, enter, leave);
        case BoxPiece::Kind::Cylinder: {
            const int i = (piece.axis + 1) % 3, j = (piece.axis + 2) % 3;
            const double oi = o[i] - piece.centre[i], oj = o[j] - piece.centre[j];
            const double a = d[i] * d[i] + d[j] * d[j], b = oi * d[i] + oj * d[j], c = oi * oi + oj * oj - r * r;
            if (a > 0) {
                double near, far;
                if (!quadraticRoots(a, b, c, near, far)) return false;
                enter = std::max(enter, near), leave = std::min(leave, far);
            } else if (!(c <= 0)) {
                return false;  // parallel to the axis, outside the tube
            }
            // Along its axis the cylinder ends with the edge.
            Box3 along(Vec3::Constant(-INFINITY), Vec3::Constant(INFINITY));
            along.lower[piece.axis] = piece.extent.lower[piece.axis];
            along.upper[piece.axis] = piece.extent.upper[piece.axis];
            return clipRayToBox(along, o, d, enter, leave);
        }
        case BoxPiece::Kind::Ball: {
            const Vec3 oc = o - piece.centre;
            double near, far;
            if (!quadraticRoots(d.squaredNorm(), oc.dot(d), oc.squaredNorm() - r * r, near, far)) return false;
            enter = std::max(enter, near), leave = std::min(leave, far);
            return enter <= leave;
        }
    }
    return false;
}

class BoxCellTracer final : public CellTracer {
public:
    BoxCellTracer(const ShapeCell<BoxField>& cell, std::vector<BoxPiece> pieces)
        : box_(*cell.shape), placement_(*cell.placement), sign_(cell.sign()), part_(cell.part), pieces_(std::move(pieces)) {}

    CellTraceResult trace(uint32_t, const Vec3& origin, const Vec3& direction, double t0, double t1,
                          const TraceSettings&) const override {
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(part_, o, d, t0, t1)) return {};
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        // The solid is convex: within [t0, t1] the ray is inside it on one
        // interval, the union of its intervals in the pieces reaching the cell.
        const Vec3 local = o - box_.center;
        double enter = INFINITY, leave = -INFINITY;
        for (const BoxPiece& piece : pieces_) {
            double e, l;
            if (!pieceInterval(piece, box_.rounding, local, d, t0, t1, e, l)) continue;
            enter = std::min(enter, e), leave = std::max(leave, l);
        }
        r.steps = 1;
        r.evaluations = pieces_.size();
        if (!(enter <= leave)) return r;
        // Entering from outside, or, when inside at t0, leaving.
        const double t = enter > t0 ? enter : leave < t1 ? leave : NAN;
        if (!std::isfinite(t)) return r;
        recordHit(r, t, box_, o, d, placement_, sign_);
        return r;
    }

private:
    BoxField box_;
    LeafPlacement placement_;
    double sign_;  ///< -1 for the complement (a carving box)
    Box3 part_;    ///< in the leaf's frame
    std::vector<BoxPiece> pieces_;
};

}  // namespace

std::optional<CellAcceleration> BoxCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                               double) const {
    const ShapeCell<BoxField> cell(program, box);
    if (!cell.shape) return std::nullopt;
    CellAcceleration a;
    if (cell.part.isEmpty()) return a;
    // The pieces that reach the part (in the box's frame).
    const Vec3& centre = cell.shape->center;
    const Box3 local(cell.part.lower - centre, cell.part.upper - centre);
    std::vector<BoxPiece> pieces;
    for (const BoxPiece& piece : piecesOf(*cell.shape))
        if (!intersection(piece.extent, local).isEmpty()) pieces.push_back(piece);
    if (pieces.empty()) return a;
    a.parts = worldPartBoxes(*cell.placement, {cell.part}, box);
    a.tracer = std::make_unique<BoxCellTracer>(cell, std::move(pieces));
    return a;
}

}  // namespace isotrace::geometry
