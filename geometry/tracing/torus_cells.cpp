#include "geometry/tracing/torus_cells.h"

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class TorusCellTracer final : public ShapeCellTracer<TorusField> {
public:
    explicit TorusCellTracer(const ShapeCell<TorusField>& cell) : ShapeCellTracer(cell) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        Vec3 o, D;
        if (!leafSegment(origin, direction, o, D, t0, t1)) return r;
        double tc;
        const Monomials<4> quartic = torusQuarticAlongRay(shape_, o, D, tc);
        BernsteinRootStats stats;
        const auto s =
            firstBernsteinRoot<4>(quartic, t0 - tc, t1 - tc, settings.epsilon / direction.norm(), &stats, settings.anyHit);
        r.steps = 1 + stats.subdivisions;
        r.evaluations = uint64_t(r.steps + stats.evaluations);
        if (!s) return r;
        recordShapeHit(r, tc + *s, o, D);
        return r;
    }
};

}  // namespace

bool TorusCellAccelerator::marchesWholeField(const FieldProgram& field, const Box3&) const {
    const TorusField* torus = bareShape<TorusField>(field);
    return torus && torus->minor < torus->major;
}

std::optional<CellAcceleration> TorusCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                                 double) const {
    const ShapeCell<TorusField> cell(program, box);
    if (!cell.shape || !(cell.shape->minor < cell.shape->major)) return std::nullopt;
    CellAcceleration a;
    if (cell.part.isEmpty()) return a;
    a.parts = worldPartBoxes(*cell.placement, {cell.part}, box);
    a.tracer = std::make_unique<TorusCellTracer>(cell);
    return a;
}

}  // namespace isotrace::geometry
