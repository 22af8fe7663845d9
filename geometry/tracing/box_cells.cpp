#include "geometry/tracing/box_cells.h"

#include <cmath>

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class BoxCellTracer final : public ShapeCellTracer<BoxField> {
public:
    BoxCellTracer(const ShapeCell<BoxField>& cell, RoundedBoxPieces pieces)
        : ShapeCellTracer(cell), pieces_(std::move(pieces)) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings&) const override {
        CellTraceResult r;
        Vec3 o, d;
        if (!leafSegment(origin, direction, o, d, t0, t1)) return r;
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
        recordShapeHit(r, t, o, d);
        return r;
    }

private:
    RoundedBoxPieces pieces_;  ///< those that reach the part
};

}  // namespace

bool BoxCellAccelerator::marchesWholeField(const FieldProgram& field, const Box3&) const {
    const BoxField* box = bareShape<BoxField>(field);
    return box && box->rounding == 0.0;
}

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
