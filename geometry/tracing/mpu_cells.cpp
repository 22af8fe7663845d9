#include "geometry/tracing/mpu_cells.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "geometry/pointsets/mpu_ray_segment.h"

namespace isotrace::geometry {

namespace {

// A part is split while it holds more locals than this, down to
// kMaxSplits halvings of its cell: a ray pays for every local its segment
// meets, and for every part it enters.
constexpr size_t kLocalsPerPart = 64;
constexpr int kMaxSplits = 2;

// A part and the band that holds its surface. Over the part's box f lies
// near the plane L(x) = value + gradient . (x - center), f's tangent plane
// at the box's centre: f - L = sum_i w_i (Q_i - L) / W (plus the faint
// background's share), and each |Q_i - L| has an interval bound D_i over the
// box. Weighing them matters: a ball grown over sparse data may disagree
// with L a hundred times more than its neighbours, where it weighs little.
// For any threshold delta,
//   |f - L| <= delta + sum over D_i > delta of w_i,max (D_i - delta) / W_min,
// and the band is the least of these over the thresholds D_i. The surface
// lies where |L| <= band: a slab a ray crosses in closed form, so rays that
// miss it cost no local function.
struct MpuPart {
    Box3 box;  ///< in the leaf's frame
    uint32_t first = 0, count = 0;
    Vec3 center = Vec3::Zero(), gradient = Vec3::Zero();
    double value = 0.0, band = 0.0;
};

Interval largerRange(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }
Interval smallerRange(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }

// The part over `box` with the locals in `locals`; false when the band
// proves the box free of surface.
bool fitBand(const MpuField& field, const Box3& box, std::span<const uint32_t> locals, MpuPart& part) {
    part.box = box;
    part.center = box.center();
    part.value = field.valueAndGradient(part.center, part.gradient, locals);
    if (!std::isfinite(part.value) || !part.gradient.allFinite()) {
        // No plane to speak of: keep the whole box.
        part.value = 0.0;
        part.gradient = Vec3::Zero();
        part.band = std::numeric_limits<double>::infinity();
        return true;
    }
    const Vec3 half = 0.5 * box.extent();
    const double planeSpread = part.gradient.cwiseAbs().dot(half);  // |L - value| over the box
    struct Deviation {
        double bound, weight;  // D_i, w_i,max
    };
    thread_local std::vector<Deviation> deviations;  // build time: grows once per thread
    deviations.clear();
    double weightBelow = MpuField::kBackgroundWeight, magnitude = std::abs(part.value);
    for (const uint32_t i : locals) {
        const MpuLocal& l = field.locals()[i];
        const Interval distance = box.distanceRange(l.center);
        if (distance.lo >= l.radius) continue;
        auto weightAt = [&](double r) { return mpuWeight(r * r, l.radius * l.radius); };
        weightBelow += weightAt(distance.hi);
        // Q - L is a quadric of the same A; centred on the box, its range
        // is its value there plus the reach of its gradient and of A over
        // the half-extents (tight, unlike a range about a far origin).
        Interval v[3];
        for (int k = 0; k < l.count; ++k) {
            const MpuQuadric& q = field.pieces()[l.first + k];
            Vec3 g;
            const double c = q.evaluate(part.center, &g) - part.value;
            const double linear = (g - part.gradient).cwiseAbs().dot(half);
            double lo = c - linear, hi = c + linear;
            for (int a = 0; a < 3; ++a) {
                const double diagonal = q.A(a, a) * half[a] * half[a];
                (diagonal < 0 ? lo : hi) += diagonal;
                for (int b = a + 1; b < 3; ++b) {
                    const double cross = 2.0 * std::abs(q.A(a, b)) * half[a] * half[b];
                    lo -= cross;
                    hi += cross;
                }
            }
            v[k] = {lo, hi};
            magnitude = std::max(magnitude, std::abs(c) + linear);
        }
        deviations.push_back({combineMpuPieces(l, v, largerRange, smallerRange).magnitude(), weightAt(distance.lo)});
    }
    std::sort(deviations.begin(), deviations.end(),
              [](const Deviation& a, const Deviation& b) { return a.bound > b.bound; });
    // Threshold delta = D_k: the k larger ones pay their excess.
    double deviation = deviations.empty() ? 0.0 : std::numeric_limits<double>::infinity();
    double weighted = 0.0, weights = 0.0;
    for (size_t k = 0; k <= deviations.size(); ++k) {
        const double delta = k < deviations.size() ? deviations[k].bound : 0.0;
        deviation = std::min(deviation, delta + (weighted - delta * weights) / weightBelow);
        if (k < deviations.size()) {
            weighted += deviations[k].weight * deviations[k].bound;
            weights += deviations[k].weight;
        }
    }
    // The background's share: weight over W, times its distance from L.
    const double background = std::abs(field.backgroundMargin() - part.value) + planeSpread;
    deviation += MpuField::kBackgroundWeight / weightBelow * background;
    part.band = deviation * (1 + 1e-9) + 1e-12 * (magnitude + planeSpread);
    return std::abs(part.value) <= part.band + planeSpread;
}

class MpuCellTracer final : public CellTracer {
public:
    MpuCellTracer(std::shared_ptr<const MpuField> field, const LeafPlacement& placement, std::vector<MpuPart> parts,
                  std::vector<uint32_t> locals)
        : field_(std::move(field)), placement_(placement), parts_(std::move(parts)), locals_(std::move(locals)) {}

    CellTraceResult trace(uint32_t index, const Vec3& origin, const Vec3& direction, double t0, double t1,
                          const TraceSettings& settings) const override {
        const MpuPart& part = parts_[index];
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(part.box, o, d, t0, t1)) return {};
        // Where the ray is within the band of the plane: |alpha + beta t| <= band.
        const double alpha = part.value + part.gradient.dot(o - part.center), beta = part.gradient.dot(d);
        if (std::abs(beta) > 0) {
            double ta = (-part.band - alpha) / beta, tb = (part.band - alpha) / beta;
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        } else if (std::abs(alpha) > part.band) {
            return {};
        }
        CellTraceResult r;
        r.steps = 1;
        if (!(t1 >= t0)) return r;
        const std::span<const uint32_t> locals(locals_.data() + part.first, part.count);
        const MpuSegmentRoot root =
            firstRootAlongSegment(*field_, locals, o, d, t0, t1, settings.epsilon / direction.norm());
        r.steps += root.pieces;
        r.evaluations = uint64_t(root.localTerms);
        if (!root.hit) return r;
        r.hit = true;
        r.t = root.t;
        Vec3 gradient;
        field_->valueAndGradient(o + root.t * d, gradient, locals);
        r.gradientKnown = true;
        r.gradient = worldGradient(placement_, gradient);
        return r;
    }

private:
    std::shared_ptr<const MpuField> field_;
    LeafPlacement placement_;
    std::vector<MpuPart> parts_;
    std::vector<uint32_t> locals_;
};

}  // namespace

std::optional<CellAcceleration> MpuCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                               double) const {
    const FieldLeaf* leaf = program.singleLeaf();
    const auto* mpu = leaf ? std::get_if<MpuLeafField>(&leaf->shape) : nullptr;
    if (!mpu) return std::nullopt;
    const MpuField& field = *mpu->field;
    // Interpolants (partitioned variational fits) are no polynomials along rays.
    if (field.hasInterpolants()) return std::nullopt;
    const LeafPlacement& placement = leaf->placement;
    const Box3 leafBox = placement.identity ? box : transformBox(placement.linear, placement.offset, box);
    // Beyond the domain the background term is a distance, not a polynomial.
    if (!field.bounds().contains(leafBox)) return std::nullopt;

    std::vector<MpuPart> parts;
    std::vector<uint32_t> locals, touching;
    auto carve = [&](auto&& self, const Box3& b, int splits) -> void {
        field.localsTouching(b, touching);
        MpuPart part;
        if (touching.size() > kLocalsPerPart && splits < kMaxSplits) {
            // Split: the cheaper convex-hull range decides whether to go on.
            if (!field.range(b).containsZero()) return;
            for (int k = 0; k < 8; ++k) self(self, b.octant(k), splits + 1);
            return;
        }
        if (!fitBand(field, b, touching, part)) return;
        part.first = uint32_t(locals.size());
        part.count = uint32_t(touching.size());
        parts.push_back(part);
        locals.insert(locals.end(), touching.begin(), touching.end());
    };
    carve(carve, leafBox, 0);

    CellAcceleration a;
    std::vector<Box3> boxes;
    for (const MpuPart& part : parts) boxes.push_back(part.box);
    a.parts = worldPartBoxes(placement, boxes, box);
    a.tracer = std::make_unique<MpuCellTracer>(mpu->field, placement, std::move(parts), std::move(locals));
    return a;
}

}  // namespace isotrace::geometry
