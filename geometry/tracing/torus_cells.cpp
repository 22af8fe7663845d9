#include "geometry/tracing/torus_cells.h"

#include "geometry/bernstein_root.h"
#include "geometry/fields/torus.h"

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
        // In s = t - tc, tc where the ray passes closest to the centre (small
        // monomials, well conditioned): g = |d|^2 + R^2 - r^2 and
        // h = d_x^2 + d_z^2 are quadratics in s, the quartic g^2 - 4 R^2 h.
        const double tc = (torus_.center - o).dot(D) / D.squaredNorm();
        const Vec3 d0 = o + tc * D - torus_.center;
        const double R2 = torus_.major * torus_.major;
        const double g0 = d0.squaredNorm() + R2 - torus_.minor * torus_.minor, g1 = 2.0 * d0.dot(D), g2 = D.squaredNorm();
        const double h0 = d0.x() * d0.x() + d0.z() * d0.z(), h1 = 2.0 * (d0.x() * D.x() + d0.z() * D.z()),
                     h2 = D.x() * D.x() + D.z() * D.z();
        const Monomials<4> quartic{g0 * g0 - 4.0 * R2 * h0, 2.0 * g0 * g1 - 4.0 * R2 * h1,
                                   g1 * g1 + 2.0 * g0 * g2 - 4.0 * R2 * h2, 2.0 * g1 * g2, g2 * g2};
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
