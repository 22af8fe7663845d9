#include "geometry/tracing/variational_cells.h"

#include "geometry/variational/patch_tracer.h"

namespace isotrace::geometry {

namespace {

class VariationalCellTracer final : public CellTracer {
public:
    // Its models are proven over its parts only.
    bool tracesFromBeforeItsPart() const override { return false; }

    VariationalCellTracer(std::vector<VariationalPatch> models, std::vector<Box3> parts,
                          std::shared_ptr<const VariationalField> field, const LeafPlacement& placement)
        : models_(std::move(models)), parts_(std::move(parts)), field_(std::move(field)), placement_(placement) {}

    CellTraceResult trace(uint32_t part, const PartBand& band, const PartPayload&, const Vec3& origin,
                          const Vec3& direction, double t0, double t1, const TraceSettings& settings) const override {
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        // The model holds inside its own box only, the surface lies in its
        // part (the world box Embree tests bounds it for identity placements).
        if (!placement_.identity && !clipRayToBox(parts_[part], o, d, t0, t1)) return {};
        // Beyond the band around the model's plane f keeps the plane's sign:
        // a ray that misses the band misses the surface (most rays offered a
        // part do), and the march can end where the ray leaves the band. Its
        // start stays, so that the sign there is proven before any anchor.
        // The band is the cell's copy of the model's plane and band: the
        // model itself is read only by rays that enter it.
        double enter, leave;
        if (!band.span(o, d, enter, leave)) return {};
        // Widened for rounding in t (relative to t: a far origin).
        const double slack = 1e-12 * (std::abs(t0) + std::abs(t1));
        if (!(leave + slack >= t0 && enter - slack <= t1)) return {};
        t1 = std::min(t1, leave + slack);
        const VariationalPatch& model = models_[part];
        const PatchTraceResult p =
            tracePatch(model, *field_, o, d, t0, t1, settings.epsilon / direction.norm(), settings.anyHit);
        CellTraceResult r;
        r.steps = p.steps + p.exactEvaluations;
        r.evaluations =
            uint64_t(p.steps) * VariationalPatch::kMonomials + uint64_t(p.exactEvaluations) * field_->termCount();
        r.t = p.t;
        if (!p.complete) {
            r.complete = false;
            r.restEnd = t1;
            return r;
        }
        r.hit = p.hit;
        r.gradientKnown = p.hit;
        r.gradient = worldGradient(placement_, p.gradient);
        return r;
    }

private:
    std::vector<VariationalPatch> models_;
    std::vector<Box3> parts_;  ///< each model's box shrunk to where it may hold surface (leaf frame)
    std::shared_ptr<const VariationalField> field_;
    LeafPlacement placement_;
};

}  // namespace

std::optional<CellAcceleration> VariationalCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                                       double surfaceDiagonal) const {
    const FieldLeaf* leaf = program.singleLeaf();
    const auto* variational = leaf ? std::get_if<VariationalLeafField>(&leaf->shape) : nullptr;
    if (!variational) return std::nullopt;
    const LeafPlacement& placement = leaf->placement;
    const Box3 leafBox = placement.identity ? box : transformBox(placement.linear, placement.offset, box);
    // Tolerance in the leaf's values: world values are valueScale times them.
    std::optional<std::vector<VariationalPatch>> models =
        buildSurfaceModels(*variational->field, leafBox, relativeTolerance_ * surfaceDiagonal / placement.valueScale,
                           maxDepth_);
    if (!models) return std::nullopt;
    // Each model's box shrunk to the sub-boxes (two bisections deep) whose
    // range by the model (VariationalPatch::rangeOver) may hold zero, then
    // to its band's slab: rays that pass the surface by are never offered
    // the rest.
    std::vector<VariationalPatch> kept;
    std::vector<Box3> parts;
    CellAcceleration a;
    for (VariationalPatch& model : *models) {
        const PartBand band{model.expansionPoint, model.planeSlope, model.coefficients[0], model.planeBand};
        const Box3 part =
            boxAroundBand(shrunkToSurface(model.box, [&model](const Box3& b) { return model.rangeOver(b); }), band);
        if (part.isEmpty()) continue;
        parts.push_back(part);
        a.bands.push_back(band);
        kept.push_back(std::move(model));
    }
    a.parts = worldPartBoxes(placement, parts, box);
    a.tracer = std::make_unique<VariationalCellTracer>(std::move(kept), std::move(parts), variational->field, placement);
    return a;
}

}  // namespace isotrace::geometry
