#include "geometry/tracing/sphere_set_cells.h"

#include <cmath>
#include <limits>

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

class SphereSetCellTracer final : public CellTracer {
public:
    SphereSetCellTracer(std::shared_ptr<const std::vector<SphereField>> all, std::vector<uint32_t> members,
                        const LeafPlacement& placement, double sign)
        : all_(std::move(all)), members_(std::move(members)), placement_(placement), sign_(sign) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload& payload, const Vec3& origin,
                          const Vec3& direction, double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        const uint32_t* members = members_.data() + payload.firstTerm;
        const uint32_t count = payload.termCount;
        r.steps = 1;
        r.evaluations = count;
        // Spans shorter than the trace's resolution are a ray touching a
        // sphere, and gaps that short between spans are rounding: neither
        // is a way in or out.
        const double resolution = settings.epsilon / direction.norm();
        constexpr double kNone = std::numeric_limits<double>::infinity();
        // Outside every sphere at t0: the first entry. Inside some: the end
        // of the chain of overlapping spans that holds t0.
        double firstEntry = kNone, exit = -kNone;
        uint32_t entering = 0, leaving = 0;
        for (uint32_t k = 0; k < count; ++k) {
            double enter, leave;
            if (!sphereSpan((*all_)[members[k]], o, d, enter, leave) || !(leave - enter > resolution)) continue;
            if (enter < t0 && leave > t0) {
                if (leave > exit) exit = leave, leaving = members[k];
            } else if (enter >= t0 && enter < firstEntry) {
                firstEntry = enter, entering = members[k];
            }
        }
        if (exit > t0) {
            // Spans that begin before the chain ends extend it.
            for (bool grew = true; grew && exit <= t1;) {
                grew = false;
                for (uint32_t k = 0; k < count; ++k) {
                    double enter, leave;
                    if (!sphereSpan((*all_)[members[k]], o, d, enter, leave) || !(leave - enter > resolution)) continue;
                    if (enter <= exit + resolution && leave > exit) exit = leave, leaving = members[k], grew = true;
                }
            }
            if (exit <= t1) hitOn(r, (*all_)[leaving], exit, o, d);
            return r;
        }
        if (firstEntry <= t1) hitOn(r, (*all_)[entering], firstEntry, o, d);
        return r;
    }

    std::optional<Absorbed> absorb(const CellAcceleration& other) override {
        const auto* tracer = dynamic_cast<const SphereSetCellTracer*>(other.tracer.get());
        if (!tracer || tracer->all_ != all_ || !(tracer->placement_ == placement_) || tracer->sign_ != sign_)
            return std::nullopt;
        const Absorbed at{parts_, uint32_t(members_.size())};
        members_.insert(members_.end(), tracer->members_.begin(), tracer->members_.end());
        parts_ += uint32_t(other.parts.size());
        return at;
    }

private:
    void hitOn(CellTraceResult& r, const SphereField& sphere, double t, const Vec3& o, const Vec3& d) const {
        recordHit(r, t, sphere, o, d, placement_, sign_);
    }

    std::shared_ptr<const std::vector<SphereField>> all_;
    std::vector<uint32_t> members_;  ///< every cell's run, one after another
    LeafPlacement placement_;
    double sign_;
    uint32_t parts_ = 1;
};

// The union of spheres a cell's program is, alone or negated (a
// difference's carving operand), or null.
const SphereSetField* closedFormUnion(const FieldProgram& program, bool& negated, const LeafPlacement*& placement) {
    const FieldLeaf* leaf = program.leafUpToSign(negated);
    const auto* set = leaf ? std::get_if<SphereSetField>(&leaf->shape) : nullptr;
    if (!set || set->operation != SetOperation::Union) return nullptr;
    placement = &leaf->placement;
    return set;
}

// A ray's segment in a cell starts up to the trace's resolution before it
// (ImplicitSurface::intersectCell; 1e-6 of the surface's diagonal): spheres
// this much farther off are kept too.
constexpr double kReachMargin = 1e-4;

}  // namespace

size_t sphereSetCellCost(const FieldProgram& program, const Box3& box) {
    bool negated = false;
    const LeafPlacement* placement = nullptr;
    if (const SphereSetField* set = closedFormUnion(program, negated, placement))
        return set->membersReaching(placement->leafFromWorld(box)).size();
    size_t members = 0;
    for (const FieldInstruction& in : program.instructions())
        if (in.op == FieldOp::Leaf)
            if (const auto* set = std::get_if<SphereSetField>(&program.leaf(in.a).shape)) members += set->members.size();
    return members;
}

std::optional<CellAcceleration> SphereSetCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                                     double surfaceDiagonal) const {
    bool negated = false;
    const LeafPlacement* placement = nullptr;
    const SphereSetField* set = closedFormUnion(program, negated, placement);
    if (!set) return std::nullopt;
    // The tracer keeps only the spheres a ray in the cell can meet; the
    // pruned program holds more, those that decide the value there.
    std::vector<uint32_t> reaching =
        set->membersReaching(placement->leafFromWorld(box.expanded(kReachMargin * surfaceDiagonal)));
    CellAcceleration a;
    // No sphere reaches in: the cell is all inside or all outside.
    if (reaching.empty()) return a;
    // The whole cell is the part: shrinking it to the surface would cost
    // up to 72 ranges of every member, most of a large set's start-up, and
    // a cell of dozens of spheres has surface throughout.
    a.parts = {box};
    PartPayload payload;
    payload.termCount = uint32_t(reaching.size());
    a.payloads = {payload};
    a.tracer = std::make_unique<SphereSetCellTracer>(set->all, std::move(reaching), *placement, negated ? -1.0 : 1.0);
    return a;
}

}  // namespace isotrace::geometry
