#include "geometry/tracing/sphere_cells.h"

#include <cmath>

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class SphereCellTracer final : public CellTracer {
public:
    explicit SphereCellTracer(const ShapeCell<SphereField>& cell)
        : sphere_(*cell.shape), placement_(*cell.placement), sign_(cell.sign()), part_(cell.part) {}

    CellTraceResult trace(uint32_t, const Vec3& origin, const Vec3& direction, double t0, double t1,
                          const TraceSettings&) const override {
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(part_, o, d, t0, t1)) return {};
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        r.steps = 1;
        r.evaluations = 1;
        double near, far;
        if (!sphereSpan(sphere_, o, d, near, far)) return r;
        const double t = near >= t0 ? near : far;
        if (!(t >= t0 && t <= t1)) return r;
        recordHit(r, t, sphere_, o, d, placement_, sign_);
        return r;
    }

private:
    SphereField sphere_;
    LeafPlacement placement_;
    double sign_;  ///< -1 for the complement (a carving sphere)
    Box3 part_;  ///< in the leaf's frame
};

}  // namespace

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
