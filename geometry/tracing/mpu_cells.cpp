#include "geometry/tracing/mpu_cells.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "geometry/pointsets/mpu_numerator_model.h"
#include "geometry/pointsets/mpu_ray_segment.h"
#include "geometry/quadratic_roots.h"

namespace isotrace::geometry {

namespace {

// A part is split while it holds more locals than this, down to
// kMaxSplits halvings of its cell: a ray pays for every local its segment
// meets, and for every part it enters.
constexpr size_t kLocalsPerPart = 64;
constexpr int kMaxSplits = 2;
// A part is split further, down to kMaxModelSplits halvings, until the
// error of its model of N (mpu_numerator_model.h) is below kModelTolerance
// of its gradient times its half diagonal. Looser, fewer spans are proven
// monotone and the exact search takes them; tighter, loading and memory
// grow for little. bench/mpu_render decides it (bench/RESULTS.md, "Tuned
// constants").
constexpr double kModelTolerance = 0.05;
constexpr int kMaxModelSplits = 4;

// A part is its cell's PartPayload, in the cache lines after its box and
// band (kept in a vector of the tracer's, it was a second dependent cache
// miss for every ray that reached a band): its run of the tracer's locals
// and the rest of its model of N, fitted over the box it was carved as
// (about that box's centre). The model's value and gradient at the centre
// are the part's PartBand: the surface lies where |L| <= band, L the
// model's tangent plane at the centre and band its error plus the reach of
// its curvature, a slab a ray crosses in closed form, so rays that miss it
// read nothing more.
PartQuadraticModel partModelOf(const MpuNumeratorModel& m) {
    const Mat3& h = m.hessian;
    return {{h(0, 0), h(0, 1), h(0, 2), h(1, 1), h(1, 2), h(2, 2)},
            m.valueError, m.slopeError, m.hessianError, m.remainderThird, m.valueFloor, m.slopeFloor};
}

// The box Embree is offered for a part: within `partBox` (inside the box
// `b` the model was fitted over), around the slab of each octant of b's own
// band (the model's tangent plane at the octant's centre, its error and its
// curvature's reach over the octant, a quarter of the whole box's), inside
// the whole box's slab. Rays leaving the surface cross the boxes of the
// parts beside their origin; on the 37,934-vertex model of
// bench/mpu_render these boxes cut the parts Embree offers by 12%
// (grandchildren's slabs: 13%, for eight times the building).
Box3 boxAroundModelSurface(const Box3& partBox, const Box3& b, const MpuNumeratorModel& m, const PartBand& whole) {
    const double octantReach = quadraticRange(0.0, Vec3::Zero(), 0.5 * m.hessian, 0.25 * b.extent()).magnitude();
    Box3 around;
    for (int k = 0; k < 8; ++k) {
        const Box3 octant = b.octant(k);
        const Box3 inPart = intersection(octant, partBox);
        if (inPart.isEmpty()) continue;
        Vec3 slope;
        const double value = m.at(octant.center(), &slope);
        const Box3 slab = boxAroundBand(inPart, {octant.center(), slope, value, m.valueError + octantReach});
        if (!slab.isEmpty()) around.extend(slab);
    }
    return intersection(around, boxAroundBand(partBox, whole));
}

// Where a ray crosses a part's band, solving N exactly as a polynomial
// turns each of the 60-80 locals listed into a polynomial of degree 8. The
// part's model needs none of that where |T| exceeds its error: N has T's
// sign there. In the spans between, where T's slope beats the slope's
// error, N is monotone: its one root (if the signs at the ends differ) is
// settled by Newton steps on the exact N, two or three point evaluations.
// Only spans not proven monotone (rays grazing the surface, or models of
// the deepest parts, kept however loose) take the exact search.
class MpuCellTracer final : public CellTracer {
public:
    // Its models are proven over its parts only.
    bool tracesFromBeforeItsPart() const override { return false; }

    MpuCellTracer(std::shared_ptr<const MpuField> field, const LeafPlacement& placement, std::vector<Box3> leafBoxes,
                  std::vector<uint32_t> locals)
        : field_(std::move(field)), placement_(placement), partCount_(leafBoxes.size()),
          leafBoxes_(placement.identity ? std::vector<Box3>() : std::move(leafBoxes)), locals_(std::move(locals)) {}

    // Another cell's parts of the same field, placed alike: their lists
    // join this tracer's, each part's `first` moved past the lists before.
    std::optional<Absorbed> absorb(const CellAcceleration& other) override {
        auto* o = dynamic_cast<MpuCellTracer*>(other.tracer.get());
        if (!o || o->field_ != field_ || o->placement_ != placement_) return std::nullopt;
        constexpr size_t kLimit = std::numeric_limits<uint32_t>::max();
        if (locals_.size() + o->locals_.size() > kLimit || partCount_ + o->partCount_ > kLimit) return std::nullopt;
        const Absorbed absorbed{uint32_t(partCount_), uint32_t(locals_.size())};
        locals_.insert(locals_.end(), o->locals_.begin(), o->locals_.end());
        leafBoxes_.insert(leafBoxes_.end(), o->leafBoxes_.begin(), o->leafBoxes_.end());
        partCount_ += o->partCount_;
        return absorbed;
    }

    CellTraceResult trace(uint32_t index, const PartBand& band, const PartPayload& payload, const Vec3& origin,
                          const Vec3& direction, double t0, double t1, const TraceSettings& settings) const override {
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(leafBoxes_[index], o, d, t0, t1)) return {};
        // Where the ray is within the band of the plane: |alpha + beta t| <= band.
        double enter, leave;
        if (!band.span(o, d, enter, leave)) return {};
        t0 = std::max(t0, enter);
        t1 = std::min(t1, leave);
        CellTraceResult r;
        r.steps = 1;
        if (!(t1 >= t0)) return r;
        const MpuLocalList locals(std::span<const uint32_t>(locals_.data() + payload.firstTerm, payload.termCount),
                                  payload.singleTerms, payload.pieceCodes);
        const double tolerance = settings.epsilon / direction.norm();
        Vec3 gradient;
        const bool hit = modelledRoot(band, payload.model, locals, o, d, t0, t1, tolerance, settings.anyHit, r, gradient);
        if (!hit) return r;
        r.hit = true;
        r.gradientKnown = true;
        r.gradient = worldGradient(placement_, gradient);
        return r;
    }

private:
    // The first root in [t0, t1] by the exact polynomial search; on a hit,
    // r.t and the gradient there.
    bool exactRoot(MpuLocalList locals, const Vec3& o, const Vec3& d, double t0, double t1,
                   double tolerance, CellTraceResult& r, Vec3& gradient) const {
        const MpuSegmentRoot root = firstRootAlongSegment(*field_, locals, o, d, t0, t1, tolerance);
        r.steps += root.pieces;
        r.evaluations += uint64_t(root.localTerms);
        return root.hit && hitAt(root.t, locals, o, d, r, gradient);
    }

    // A hit at t, with N's gradient there.
    bool hitAt(double t, MpuLocalList locals, const Vec3& o, const Vec3& d, CellTraceResult& r,
               Vec3& gradient) const {
        r.t = t;
        gradient = field_->blendSums(o + t * d, locals).gradient();
        return true;
    }

    // The same through the part's model of N: spans where |T| exceeds its
    // error have T's sign; each span between is searched, in order.
    // With anyHit (an occlusion query), a root proven between two signs is
    // enough: it is reported halfway, with the model's gradient, and N is
    // not evaluated to settle it.
    bool modelledRoot(const PartBand& plane, const PartQuadraticModel& m, MpuLocalList locals, const Vec3& o,
                      const Vec3& d, double t0, double t1, double tolerance, bool anyHit, CellTraceResult& r,
                      Vec3& gradient) const {
        // Most segments a ray meets keep T beyond the part's whole error
        // (|N - T| <= valueError): N keeps T's sign, and no root is near.
        // T's range over the segment, from its ends and its vertex, says so
        // without the errors of the segment's reach or the spans' roots.
        {
            const ModelAlongRay T(plane, m, o, d);
            const double at0 = T(t0), at1 = T(t1);
            double lo = std::min(at0, at1), hi = std::max(at0, at1);
            if (T.c2 != 0.0) {
                const double vertex = -T.c1 / (2.0 * T.c2);
                if (vertex > t0 && vertex < t1) {
                    lo = std::min(lo, T(vertex));
                    hi = std::max(hi, T(vertex));
                }
            }
            if (lo > m.valueError || hi < -m.valueError) return false;
        }
        const NearErrors whole = nearErrors(plane, m, o, d, t0, t1);
        return spansRoot(plane, m, locals, o, d, t0, t1, whole.value, whole.slope, 0, 0, true, tolerance, anyHit, r,
                         gradient);
    }

    // The part's model T along the ray: c0 + c1 t + c2 t^2.
    struct ModelAlongRay {
        double c0, c1, c2;
        ModelAlongRay(const PartBand& plane, const PartQuadraticModel& m, const Vec3& o, const Vec3& d) {
            const Vec3 y0 = o - plane.point, hd = m.times(d);
            c0 = plane.value + plane.slope.dot(y0) + 0.5 * y0.dot(m.times(y0));
            c1 = plane.slope.dot(d) + y0.dot(hd);
            c2 = 0.5 * d.dot(hd);
        }
        double operator()(double t) const { return c0 + t * (c1 + t * c2); }
    };

    // The model's errors over the ray's segment [a, b]: within distance r of
    // the centre Taylor's remainder is M3 r^3 / 6 (slope: M3 r^2 / 2), and a
    // segment's farthest point from the centre is one of its ends. Where a
    // crease crosses the part, the whole part's errors.
    struct NearErrors {
        double value, slope;  ///< the slope's per unit of length
    };
    static NearErrors nearErrors(const PartBand& plane, const PartQuadraticModel& m, const Vec3& o, const Vec3& d, double a,
                                 double b) {
        if (!std::isfinite(m.hessianError)) return {m.valueError, m.slopeError};
        const double reach = std::max((o + a * d - plane.point).norm(), (o + b * d - plane.point).norm());
        const MpuTaylorRemainder near = mpuTaylorRemainder(m.remainderThird, reach, m.valueFloor, m.slopeFloor);
        return {std::min(m.valueError, near.value), std::min(m.slopeError, near.slope)};
    }

    // The first root in [t0, t1] on the model with value error e and slope
    // error slopeErrorPerUnit (per unit of length); the signs of N just
    // before t0 and after t1, where known (0 if not). A span the errors
    // leave undecided is looked at again with the errors of its own
    // distance from the centre (Taylor's remainder grows as its cube), if
    // allowed and clearly smaller, before the exact search takes it.
    bool spansRoot(const PartBand& plane, const PartQuadraticModel& m, MpuLocalList locals, const Vec3& o,
                   const Vec3& d, double t0, double t1, double e, double slopeErrorPerUnit, int outerLeft,
                   int outerRight, bool mayNarrow, double tolerance, bool anyHit, CellTraceResult& r,
                   Vec3& gradient) const {
        const ModelAlongRay T(plane, m, o, d);
        const double c0 = T.c0, c1 = T.c1, c2 = T.c2;
        const double slopeError = slopeErrorPerUnit * d.norm();
        auto rootBetween = [&](double a, double b) {
            r.t = 0.5 * (a + b);
            gradient = plane.slope + m.times(o + r.t * d - plane.point);
            return true;
        };
        auto modelSlope = [&](double t) { return c1 + 2.0 * c2 * t; };
        double cuts[6] = {t0};
        int cutCount = 1;
        quadraticRootsBetween(c2, c1, c0 - e, t0, t1, cuts, cutCount);
        quadraticRootsBetween(c2, c1, c0 + e, t0, t1, cuts, cutCount);
        for (int i = 2; i < cutCount; ++i)  // insertion sort of at most four
            for (int j = i; j > 1 && cuts[j - 1] > cuts[j]; --j) std::swap(cuts[j - 1], cuts[j]);
        cuts[cutCount++] = t1;
        struct Span {
            double a, b;
            int sign;  ///< N's proven sign, 0 where T cannot tell
        };
        Span spans[5];
        int count = 0;
        for (int k = 0; k + 1 < cutCount; ++k) {
            const double mid = 0.5 * (cuts[k] + cuts[k + 1]), v = T(mid);
            const int sign = v > e ? 1 : v < -e ? -1 : 0;
            if (count > 0 && spans[count - 1].sign == sign)
                spans[count - 1].b = cuts[k + 1];
            else
                spans[count++] = {cuts[k], cuts[k + 1], sign};
        }
        for (int k = 0; k < count; ++k) {
            const Span& s = spans[k];
            if (s.sign != 0) {
                // Opposite proven signs side by side (the band between them
                // lost to rounding): the exact search settles their meeting.
                if (k > 0 && spans[k - 1].sign == -s.sign &&
                    (anyHit ? rootBetween(spans[k - 1].a, s.b)
                            : exactRoot(locals, o, d, spans[k - 1].a, s.b, tolerance, r, gradient)))
                    return true;
                continue;
            }
            int left = k > 0 ? spans[k - 1].sign : outerLeft, right = k + 1 < count ? spans[k + 1].sign : outerRight;
            const double slopeA = modelSlope(s.a), slopeB = modelSlope(s.b);
            const double least = std::min(std::abs(slopeA), std::abs(slopeB)) - slopeError;
            if (!((slopeA > 0) == (slopeB > 0) && least > 0)) {
                // Not proven monotone (a ray grazing the surface, or a loose
                // model): nearer the centre, the errors may decide it.
                if (mayNarrow) {
                    const NearErrors near = nearErrors(plane, m, o, d, s.a, s.b);
                    if (near.value < 0.5 * e) {
                        if (spansRoot(plane, m, locals, o, d, s.a, s.b, near.value, near.slope, left, right, false,
                                      tolerance, anyHit, r, gradient))
                            return true;
                        continue;
                    }
                }
                if (exactRoot(locals, o, d, s.a, s.b, tolerance, r, gradient)) return true;
                continue;
            }
            // N is monotone over the span, |N'| >= least: one root at most.
            auto signAt = [&](double t) {
                const Vec3 x = o + t * d;
                if (lastSign_.field == field_->id() && lastSign_.point == x) return lastSign_.sign;
                const double n = field_->numerator(x, locals);
                r.evaluations += locals.indices.size();
                ++r.steps;
                lastSign_ = {field_->id(), x, n > 0 ? 1 : n < 0 ? -1 : 0};
                return lastSign_.sign;
            };
            // Rising, N has no root in the span when N(a) > 0 or N(b) < 0
            // (falling, the reverse): one end's sign may settle it.
            const bool rising = slopeA > 0;
            auto provesNone = [&] { return (left != 0 && (left > 0) == rising) || (right != 0 && (right < 0) == rising); };
            if (provesNone()) continue;
            double start[2];
            int found = 0;
            quadraticRootsBetween(c2, c1, c0, s.a, s.b, start, found);
            if (anyHit || (found == 0 && (left == 0 || right == 0))) {
                // The signs at the ends decide (N alone, cheaper than the
                // gradient a settled root needs): an occlusion query stops
                // at a proven root, and a span where T has no root rarely
                // holds one. The end on T's side of zero is asked first: it
                // is the one likely to prove the span empty.
                const bool aFirst = (T(0.5 * (s.a + s.b)) > 0) == rising;
                for (int pass = 0; pass < 2 && !provesNone(); ++pass) {
                    if ((pass == 0) == aFirst) {
                        if (left == 0 && (left = signAt(s.a)) == 0) return hitAt(s.a, locals, o, d, r, gradient);
                    } else if (right == 0 && (right = signAt(s.b)) == 0) {
                        right = rising ? 1 : -1;  // the root is s.b itself: N changes sign there
                    }
                }
                if (provesNone()) continue;
                if (anyHit) return rootBetween(s.a, s.b);
            }
            // |N''| along the ray: T's, plus the Hessian's error.
            const double curvature = 2.0 * std::abs(c2) + m.hessianError * d.squaredNorm();
            if (monotoneRoot(locals, o, d, s.a, s.b, left, right, rising, least, curvature,
                             found > 0 ? start[0] : 0.5 * (s.a + s.b), signAt, tolerance, r, gradient))
                return true;
        }
        return false;
    }

    // The root of N in the span (a, b) where N is monotone (rising or not),
    // |N'| >= least, |N''| <= curvature, and has sign `left` at a and `right`
    // at b (0 where not known), if it holds one. N is evaluated first at p
    // (T's root): the root lies on the side where N falls towards 0, within
    // |N(p)| / least of p, so where that reach stays inside the span the
    // root is proven there without N's sign at the span's end; only where it
    // does not is the end's sign asked (signAt).
    template <class SignAt>
    bool monotoneRoot(MpuLocalList locals, const Vec3& o, const Vec3& d, double a, double b, int left,
                      int right, bool rising, double least, double curvature, double p, SignAt&& signAt,
                      double tolerance, CellTraceResult& r, Vec3& gradient) const {
        const MpuBlendSums sums = field_->blendSums(o + p * d, locals);
        r.evaluations += locals.indices.size();
        ++r.steps;
        const double n = sums.N;
        if (n == 0.0) {
            r.t = p;
            gradient = sums.gradient();
            return true;
        }
        const int signP = n > 0 ? 1 : -1;
        const bool before = (n > 0) == rising;  // the root lies before p
        const double reach = std::abs(n) / least;
        double lo = p, hi = p;
        if (before) {
            lo = p - reach;
            if (lo < a) {
                if (left == 0 && (left = signAt(a)) == 0) return hitAt(a, locals, o, d, r, gradient);
                if (left == signP) return false;
                lo = a;
            }
        } else {
            hi = p + reach;
            if (hi > b) {
                if (right == 0 && (right = signAt(b)) == 0) right = -signP;  // the root is b itself
                if (right == signP) return false;
                hi = b;
            }
        }
        // The bracket [lo, hi] holds the root; N's sign at lo is -signP when
        // the root is before p, signP after.
        return settledRoot(locals, o, d, lo, hi, before ? -signP : signP, least, curvature, p, sums, tolerance, r,
                           gradient);
    }

    // The one root of N in [a, b], where N has sign `left` at a, the other at
    // b, |N'| >= least and |N''| <= curvature, from N's sums at p (in the
    // bracket): Newton steps on the exact N, kept inside the bracket.
    // delta = |N(p)| / least bounds p's distance to the root, and the Newton
    // step from p lands within curvature delta^2 / (2 least) of it: when
    // that is within tolerance, the step is taken without evaluating N at
    // its end (the gradient is p's, delta away).
    bool settledRoot(MpuLocalList locals, const Vec3& o, const Vec3& d, double a, double b, int left,
                     double least, double curvature, double p, MpuBlendSums sums, double tolerance,
                     CellTraceResult& r, Vec3& gradient) const {
        for (int iteration = 0; iteration < 100; ++iteration) {
            if (iteration > 0) {
                sums = field_->blendSums(o + p * d, locals);
                r.evaluations += locals.indices.size();
                ++r.steps;
            }
            const double n = sums.N;
            if (n == 0.0 || std::abs(n) <= least * tolerance) {
                r.t = p;
                gradient = sums.gradient();
                return true;
            }
            ((n > 0) == (left > 0) ? a : b) = p;
            if (b - a <= tolerance) {
                r.t = p;
                gradient = sums.gradient();
                return true;
            }
            double next = p - n / sums.gradientN.dot(d);
            const double delta = std::abs(n) / least;
            if (next > a && next < b && curvature * delta * delta <= 2.0 * least * tolerance) {
                r.t = next;
                gradient = sums.gradient();
                return true;
            }
            // Outside the bracket, or crawling: halve it instead.
            if (!(next > a && next < b) || iteration >= 8) next = 0.5 * (a + b);
            p = next;
        }
        return hitAt(p, locals, o, d, r, gradient);  // unreachable in practice: 100 halvings of a finite span
    }

    // The last sign evaluated on this thread: a ray that leaves one part
    // inside the band around the surface enters the next at the same point
    // (the parts share the face), and its sign there is already known. Any
    // list of locals reaching the point gives N there.
    struct LastSign {
        uint64_t field = 0;  ///< its id (ids are never reused, addresses may be)
        Vec3 point = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
        int sign = 0;
    };
    static thread_local LastSign lastSign_;

    std::shared_ptr<const MpuField> field_;
    LeafPlacement placement_;
    size_t partCount_ = 0;  ///< parts of all the cells it marches
    /// Each part's box in the leaf's frame, where that is not the world's
    /// (the world box, which the caller clips to, serves otherwise).
    std::vector<Box3> leafBoxes_;
    std::vector<uint32_t> locals_;
};

thread_local MpuCellTracer::LastSign MpuCellTracer::lastSign_;

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
    const Box3 leafBox = placement.leafFromWorld(box);
    // Beyond the domain the background term is a distance, not a polynomial.
    if (!field.bounds().contains(leafBox)) return std::nullopt;

    std::vector<PartPayload> parts;
    std::vector<Box3> boxes;      // parallel to parts, in the leaf's frame
    std::vector<PartBand> bands;  // parallel to parts
    std::vector<uint32_t> locals, touching;
    // A part over `b` whose locals are locals[first, first + count) (its
    // ancestor's list, shared by the parts carved from it): modelled where
    // its model is accurate enough, split while it is not; at the deepest
    // level, modelled however loosely (the model still proves most signs,
    // and the exact search takes what it cannot).
    // The carved box's locals, gathered once for the models of every box
    // carved from it; and per level of splitting, its sharp locals that the
    // model being split proves to take one piece all over its box (its
    // children sum them as single pieces).
    MpuLocalColumns columns;
    MpuLocalColumns resolvedAt[kMaxModelSplits + 1];
    auto keep = [&](auto&& self, const Box3& b, int splits, uint32_t first, uint32_t count,
                    const MpuNumeratorModel* parent, const MpuLocalColumns* resolved) -> void {
        const Vec3 half = 0.5 * b.extent();
        if (parent) {
            // The parent's model holds over this box too: it may prove it
            // free of surface before a model of its own is fitted.
            Vec3 slope;
            const double value = parent->at(b.center(), &slope);
            const Interval t = quadraticRange(value, slope, 0.5 * parent->hessian, half);
            if (t.lo > parent->valueError || t.hi < -parent->valueError) return;
        }
        // T's reach from its tangent plane over the box, and N's.
        auto bandOf = [&](const MpuNumeratorModel& m) {
            return m.valueError + quadraticRange(0.0, Vec3::Zero(), 0.5 * m.hessian, half).magnitude();
        };
        auto holdsNoSurface = [&](const MpuNumeratorModel& m) {
            return std::abs(m.value) > bandOf(m) + m.gradient.cwiseAbs().dot(half);
        };
        auto accurate = [&](const MpuNumeratorModel& m) {
            return m.valueError <= kModelTolerance * m.gradient.norm() * half.norm();
        };
        // Each box is bounded anew: the third derivatives at its own centre
        // bound its errors more tightly than a bound taken over from its
        // parent (whose balls' rims are more likely to cross it; taking it
        // over rendered 0.93x where own bounds render 0.89x).
        const MpuNumeratorModel model = fitMpuNumeratorModel(field, b, columns, resolved);
        if (holdsNoSurface(model)) return;
        if (!accurate(model) && splits < kMaxModelSplits) {
            MpuLocalColumns& within = resolvedAt[splits + 1];
            within.assignResolved(field, resolved, (resolved ? resolved : &columns)->sharp(), model);
            for (int k = 0; k < 8; ++k) self(self, b.octant(k), splits + 1, first, count, &model, &within);
            return;
        }
        // Embree is offered the box shrunk, two halvings deep, to where the
        // model's range may hold zero, and then to its octants' slabs: rays
        // that pass its corners never call the tracer.
        const MpuNumeratorModel& m = model;
        const Box3 partBox = shrunkToSurface(b, [&m](const Box3& sub) {
            Vec3 slope;
            const double value = m.at(sub.center(), &slope);
            const Interval t = quadraticRange(value, slope, 0.5 * m.hessian, 0.5 * sub.extent());
            return Interval{t.lo - m.valueError, t.hi + m.valueError};
        });
        if (partBox.isEmpty()) return;
        const PartBand band{b.center(), m.gradient, m.value, bandOf(m)};
        const Box3 around = boxAroundModelSurface(partBox, b, m, band);
        if (around.isEmpty()) return;
        boxes.push_back(around);
        bands.push_back(band);
        PartPayload part;
        part.model = partModelOf(m);
        part.firstTerm = first;
        part.termCount = count;
        part.singleTerms = uint32_t(columns.singleCount());
        // Sharp locals whose crease stays off the box are evaluated as their
        // one piece there.
        part.pieceCodes = mpuResolvedSharpPieces(
            field, m, MpuLocalList(std::span<const uint32_t>(locals.data() + first, count), part.singleTerms));
        parts.push_back(part);
    };
    auto carve = [&](auto&& self, const Box3& b, int splits) -> void {
        field.localsTouching(b, touching);
        if (touching.size() > kLocalsPerPart && splits < kMaxSplits) {
            // Split: the cheaper convex-hull range decides whether to go on.
            if (!field.range(b).containsZero()) return;
            for (int k = 0; k < 8; ++k) self(self, b.octant(k), splits + 1);
            return;
        }
        const uint32_t first = uint32_t(locals.size()), count = uint32_t(touching.size());
        const size_t kept = parts.size();
        field.singlesFirst(touching);  // a part's sums take those in vector lanes
        locals.insert(locals.end(), touching.begin(), touching.end());
        columns.assign(field, touching);
        keep(keep, b, splits, first, count, nullptr, nullptr);
        if (parts.size() == kept) locals.resize(first);  // no part holds surface
    };
    carve(carve, leafBox, 0);

    CellAcceleration a;
    a.parts = worldPartBoxes(placement, boxes, box);
    a.bands = std::move(bands);
    a.payloads = std::move(parts);
    a.tracer = std::make_unique<MpuCellTracer>(mpu->field, placement, std::move(boxes), std::move(locals));
    return a;
}

}  // namespace isotrace::geometry
