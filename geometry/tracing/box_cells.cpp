#include "geometry/tracing/box_cells.h"

#include <cmath>

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class BoxCellTracer final : public CellTracer {
public:
    BoxCellTracer(const ShapeCell<BoxField>& cell, RoundedBoxPieces pieces)
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
        double enter, leave;
        const bool inside = pieces_.span(o, d, t0, t1, enter, leave);
        r.steps = 1;
        r.evaluations = pieces_.pieceCount();
        if (!inside) return r;
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
    RoundedBoxPieces pieces_;
};

}  // namespace

std::optional<CellAcceleration> BoxCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                               double) const {
    const ShapeCell<BoxField> cell(program, box);
    if (!cell.shape) return std::nullopt;
    CellAcceleration a;
    if (cell.part.isEmpty()) return a;
    // The pieces that reach the part.
    RoundedBoxPieces pieces(*cell.shape, cell.part);
    if (pieces.empty()) return a;
    a.parts = worldPartBoxes(*cell.placement, {cell.part}, box);
    a.tracer = std::make_unique<BoxCellTracer>(cell, std::move(pieces));
    return a;
}

}  // namespace isotrace::geometry
