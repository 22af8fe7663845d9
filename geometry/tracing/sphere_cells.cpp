#include "geometry/tracing/sphere_cells.h"

#include <cmath>

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class SphereCellTracer final : public ShapeCellTracer<SphereField> {
public:
    explicit SphereCellTracer(const ShapeCell<SphereField>& cell) : ShapeCellTracer(cell) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings&) const override {
        CellTraceResult r;
        Vec3 o, d;
        if (!leafSegment(origin, direction, o, d, t0, t1)) return r;
        r.steps = 1;
        r.evaluations = 1;
        double near, far;
        if (!sphereSpan(shape_, o, d, near, far)) return r;
        const double t = near >= t0 ? near : far;
        if (!(t >= t0 && t <= t1)) return r;
        recordShapeHit(r, t, o, d);
        return r;
    }
};

}  // namespace

bool SphereCellAccelerator::marchesWholeField(const FieldProgram& field, const Box3&) const {
    return bareShape<SphereField>(field) != nullptr;
}

std::optional<CellAcceleration> SphereCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                                  double) const {
    const ShapeCell<SphereField> cell(program, box);
    if (!cell.shape) return std::nullopt;
    CellAcceleration a;
    if (cell.part.isEmpty()) return a;
    a.parts = worldPartBoxes(*cell.placement, {cell.part}, box);
    a.tracer = std::make_unique<SphereCellTracer>(cell);
    return a;
}

}  // namespace isotrace::geometry
