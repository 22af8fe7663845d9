#include "geometry/tracing/torus_cells.h"

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class TorusCellTracer final : public CellTracer {
public:
    explicit TorusCellTracer(const ShapeCell<TorusField>& cell)
        : torus_(*cell.shape), placement_(*cell.placement), sign_(cell.sign()), part_(cell.part) {}

    CellTraceResult trace(uint32_t, const Vec3& origin, const Vec3& direction, double t0, double t1,
                          const TraceSettings& settings) const override {
        Vec3 o, D;
        rayInLeafFrame(placement_, origin, direction, o, D);
        if (!placement_.identity && !clipRayToBox(part_, o, D, t0, t1)) return {};
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        double tc;
        const Monomials<4> quartic = torusQuarticAlongRay(torus_, o, D, tc);
        BernsteinRootStats stats;
        const auto s = firstBernsteinRoot<4>(quartic, t0 - tc, t1 - tc, settings.epsilon / direction.norm(), &stats);
        r.steps = 1 + stats.subdivisions;
        r.evaluations = uint64_t(r.steps + stats.evaluations);
        if (!s) return r;
        recordHit(r, tc + *s, torus_, o, D, placement_, sign_);
        return r;
    }

private:
    TorusField torus_;
    LeafPlacement placement_;
    double sign_;  ///< -1 for the complement (a carving torus)
    Box3 part_;    ///< in the leaf's frame
};

}  // namespace

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
