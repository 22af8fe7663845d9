#include "geometry/tracing/partitioned_variational_cells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "geometry/bracketed_root.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/pointsets/mpu_weight_bounds.h"
#include "geometry/variational/variational_patch.h"

namespace isotrace::geometry {

namespace {

// Along a ray, f = N / W with W > 0, where N = sum_i w_i s_i plus the
// background's constant share (parts lie inside the domain) and w_i =
// (1 - |x - c_i|^2 / R_i^2)^3. Each interpolant s_i has a model T_i over the
// part with |s_i - T_i| <= e_i, so N lies within sum_i w_i e_i of the
// models' sum: where that excludes zero, its sign is proven. A step needs a
// bound on |grad N| (not on |grad f|: a local that fits its points poorly
// far from them would inflate that one):
//   |grad N| <= sum_i |grad w_i| |s_i| + w_i |grad s_i|,
// over a ball of radius h around the point, with |s_i| <= |T_i| + e_i +
// L_i h (L_i the model's gradient bound over the part), and w_i and
// |grad w_i| at the distances [d_i - h, d_i + h] from c_i.
//
// Near the surface, where the models cannot tell the sign, one exact value
// and gradient of f anchors them, as in variational_cells: the error
// E = N - sum_i w_i T_i is then known at the anchor with its slope along
// the ray, and it drifts from there at most as fast as bounds on grad E and
// D^2 E allow (from the models' gradient and Hessian errors and the
// weights' derivatives: |grad w| <= 1.72 / R, ||D^2 w|| <= 12 / R^2).

// Models worse than this (relative to the surface's diagonal) split the
// part, twice at most: on the partitioned hand a second halving halves the
// render (1.77 -> 0.87 s at 64x48) for 1.7 s more loading and 60 MB.
constexpr double kRelativeTolerance = 1e-3;
constexpr int kMaxSplits = 2;
// Models sum their near centres exactly at every step: where those are more
// than this share of the interpolants' centres (dense data in a large part),
// a model saves too little for its memory, and the cell is left to the
// general tracer (measured on a 37,822-vertex model: 0.5 was slower than
// exact marching there, 0.25 faster).
constexpr double kMostNearShare = 0.25;
// Locals per part (a step's work and its stack arrays).
constexpr size_t kMaxLocals = 96;
// max ||D^2 w|| R^2 (max |grad w| R is kMpuWeightSlope).
constexpr double kWeightCurvature = 12.0;

struct ModelledLocal {
    Vec3 center;
    double radius, inverseRadius2;
    double valueError, lipschitz, evaluationNoise;
};

struct ModelledPart {
    Box3 box;  ///< in the leaf's frame
    uint32_t first = 0, count = 0;
    /// Bounds on |grad E| and ||D^2 E|| over the box (E: see above).
    double errorSlope = 0.0, errorCurvature = 0.0;
};

class PartitionedVariationalCellTracer final : public CellTracer {
public:
    // Its models are proven over its parts only.
    bool tracesFromBeforeItsPart() const override { return false; }

    PartitionedVariationalCellTracer(std::shared_ptr<const MpuField> field, const LeafPlacement& placement,
                                     std::vector<ModelledPart> parts, std::vector<ModelledLocal> locals,
                                     std::vector<uint32_t> localIndices, std::vector<VariationalPatch> models)
        : field_(std::move(field)), placement_(placement), parts_(std::move(parts)), locals_(std::move(locals)),
          localIndices_(std::move(localIndices)), models_(std::move(models)),
          background_(MpuField::kBackgroundWeight * field_->backgroundMargin()) {}

    CellTraceResult trace(uint32_t index, const PartBand&, const PartPayload&, const Vec3& origin,
                          const Vec3& direction, double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        const ModelledPart& part = parts_[index];
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(part.box, o, d, t0, t1)) return r;
        const double speed = direction.norm(), leafSpeed = d.norm();
        if (!(speed > 0) || !(leafSpeed > 0) || !(t1 >= t0)) return r;
        const double minStep = settings.epsilon / speed;
        int modelSteps = 0, exactSteps = 0;
        uint64_t modelTerms = 0;  // the models' monomials and near terms summed
        auto finish = [&](bool hit, double t) {
            r.hit = hit;
            r.t = t;
            r.steps = modelSteps + exactSteps;
            r.evaluations = modelTerms + uint64_t(exactSteps) * field_->termCount();
            return r;
        };
        struct Anchor {
            bool set = false;
            double t = 0, offset = 0, offsetSlope = 0;
        } anchor;
        // N at t on the models: its interval [lo, hi], its best estimate,
        // and what a step from t needs (the weights' sum, the models' values
        // and distances, for the slope bound).
        struct Sum {
            double model = 0, lo = 0, hi = 0, centre = 0, weight = 0;
            std::array<double, kMaxLocals> value, distance;
        };
        auto sum = [&](double t, Sum& n) {
            const Vec3 x = o + t * d;
            double error = 0.0, noise = 0.0;
            n.model = background_;
            n.weight = MpuField::kBackgroundWeight;
            for (uint32_t k = 0; k < part.count; ++k) {
                const ModelledLocal& l = locals_[part.first + k];
                n.distance[k] = (x - l.center).norm();
                const double q = 1.0 - n.distance[k] * n.distance[k] * l.inverseRadius2;
                if (!(q > 0)) {
                    n.value[k] = std::numeric_limits<double>::quiet_NaN();  // evaluated if a step needs it
                    continue;
                }
                const double weight = q * q * q;
                const VariationalPatch& model = models_[part.first + k];
                n.value[k] = model.value(x);
                modelTerms += VariationalPatch::kMonomials + model.nearTermCount();
                n.model += weight * n.value[k];
                error += weight * l.valueError;
                noise += weight * l.evaluationNoise;
                n.weight += weight;
            }
            ++modelSteps;
            n.lo = n.model - error;
            n.hi = n.model + error;
            n.centre = n.model;
            if (!anchor.set) return;
            const double dt = std::abs(t - anchor.t);
            const double first = n.model + anchor.offset, firstDrift = part.errorSlope * leafSpeed * dt + noise;
            const double second = first + anchor.offsetSlope * (t - anchor.t),
                         secondDrift = 0.5 * part.errorCurvature * leafSpeed * leafSpeed * dt * dt + noise;
            n.lo = std::max({n.lo, first - firstDrift, second - secondDrift});
            n.hi = std::min({n.hi, first + firstDrift, second + secondDrift});
            n.centre = second;
        };
        // One exact value and gradient of f at t: N = W f, grad N = W grad f + f grad W.
        auto anchorAt = [&](double t) {
            const Vec3 x = o + t * d;
            Vec3 gradient;
            const double f = field_->valueAndGradient(
                x, gradient, std::span<const uint32_t>(localIndices_.data() + part.first, part.count));
            ++exactSteps;
            double model = background_, weights = MpuField::kBackgroundWeight;
            Vec3 modelGradient = Vec3::Zero(), weightGradient = Vec3::Zero();
            accumulateGradients(part, x, model, weights, modelGradient, weightGradient);
            const double exact = weights * f;
            const Vec3 exactGradient = weights * gradient + f * weightGradient;
            anchor = {true, t, exact - model, (exactGradient - modelGradient).dot(d)};
        };
        // The span of t around t proven free of zeros, given a margin there:
        // each ball radius h proves min(h, margin / bound(h)); a few radii
        // about the distance f suggests are tried, the best kept.
        auto provenRadius = [&](double t, Sum& n, double margin) {
            auto bound = [&](double h) {
                double slope = 0.0;
                for (uint32_t k = 0; k < part.count; ++k) {
                    const ModelledLocal& l = locals_[part.first + k];
                    const double a = std::max(n.distance[k] - h, 0.0);
                    if (a >= l.radius) continue;
                    // A ball the point lies outside but the step's reaches:
                    // its interpolant's value at the point bounds it there.
                    if (std::isnan(n.value[k])) {
                        n.value[k] = models_[part.first + k].value(o + t * d);
                        modelTerms += VariationalPatch::kMonomials + models_[part.first + k].nearTermCount();
                    }
                    const double slopeMax = mpuWeightSlope({a, n.distance[k] + h}, l.radius);
                    const double weightMax = mpuWeight(a * a, l.radius * l.radius);
                    slope += slopeMax * (std::abs(n.value[k]) + l.valueError + l.lipschitz * h) + weightMax * l.lipschitz;
                }
                return std::min(h, margin / std::max(slope, 1e-300));
            };
            const double distance = std::abs(n.centre) / n.weight;
            double best = 0.0;
            for (const double factor : {1.0, 2.0, 4.0}) {
                const double proven = bound(factor * distance);
                best = std::max(best, proven);
                if (proven < factor * distance) break;  // larger balls prove less
            }
            return best / leafSpeed;
        };
        auto modelled = [&](double u) {
            Sum n;
            sum(u, n);
            return n.centre;
        };

        int previousSign = 0;
        double t = t0, tPrevious = t0;
        Sum n;
        while (modelSteps + exactSteps < settings.maxSteps) {
            sum(t, n);
            if (n.lo <= 0 && n.hi >= 0 && !(anchor.set && anchor.t == t)) {
                anchorAt(t);
                sum(t, n);
            }
            int sign = 0;
            double margin = 0.0;
            if (n.lo > 0) {
                sign = 1, margin = n.lo;
            } else if (n.hi < 0) {
                sign = -1, margin = -n.hi;
            } else {
                // Within rounding of the surface at the anchor: the best
                // estimate's sign (0: on it).
                sign = n.centre < 0 ? -1 : (n.centre > 0 ? 1 : 0);
            }
            const double radius = margin > 0 ? provenRadius(t, n, margin) : 0.0;
            if (sign == 0) return hitAt(finish(true, t), part, o, d);
            if (previousSign != 0 && sign != previousSign) {
                // The root is in [tPrevious, t], a forced step at most: on
                // the anchored models where their drift over the bracket is
                // far below the resolution (anchored again at t if the first
                // anchor is too far), else exactly.
                int evaluations = 0;
                double root = NAN;
                auto settle = [&] {
                    if (!anchor.set) return false;
                    const double dt = std::max(std::abs(t - anchor.t), std::abs(tPrevious - anchor.t));
                    const double drift = 0.5 * part.errorCurvature * leafSpeed * leafSpeed * dt * dt;
                    const double fa = modelled(tPrevious), fb = modelled(t);
                    const double slope = std::abs(fb - fa) / std::max(t - tPrevious, 1e-300);
                    if ((fa < 0) == (fb < 0) || drift > 1e-2 * minStep * slope) return false;
                    root = bracketedRoot(modelled, tPrevious, fa, t, fb, 1e-3 * minStep, &evaluations);
                    modelSteps += evaluations;
                    return true;
                };
                if (!settle() && !(anchor.set && anchor.t == t)) {
                    anchorAt(t);
                    settle();
                }
                if (std::isnan(root)) {
                    auto exact = [&](double u) { return field_->value(o + u * d); };
                    const double fa = exact(tPrevious), fb = exact(t);
                    exactSteps += 2;
                    if ((fa < 0) == (fb < 0)) {
                        previousSign = 0;  // rounding: start afresh from here
                        continue;
                    }
                    root = bracketedRoot(exact, tPrevious, fa, t, fb, 1e-3 * minStep, &evaluations);
                    exactSteps += evaluations;
                }
                return hitAt(finish(true, root), part, o, d);
            }
            previousSign = sign;
            tPrevious = t;
            if (t >= t1) return finish(false, 0.0);
            const bool forced = radius < minStep;  // may skip a sliver thinner than epsilon, as the general tracer's
            if (!forced && t + radius >= t1) return finish(false, 0.0);
            t = std::min(t + std::max(radius, minStep), t1);
        }
        // Out of steps (a ray grazing the surface): the general tracer
        // settles the rest from the last point whose sign is known.
        finish(false, tPrevious);
        r.complete = false;
        r.restEnd = t1;
        return r;
    }

private:
    // Adds the models' weighted values and gradients and the weights'
    // gradients at x to the sums given.
    void accumulateGradients(const ModelledPart& part, const Vec3& x, double& model, double& weights,
                             Vec3& modelGradient, Vec3& weightGradient) const {
        for (uint32_t k = 0; k < part.count; ++k) {
            const ModelledLocal& l = locals_[part.first + k];
            const Vec3 away = x - l.center;
            const double q = 1.0 - away.squaredNorm() * l.inverseRadius2;
            if (!(q > 0)) continue;
            Vec3 g;
            const double value = models_[part.first + k].valueAndGradient(x, g);
            const double weight = q * q * q;
            const Vec3 slope = (-6.0 * q * q * l.inverseRadius2) * away;
            model += weight * value;
            weights += weight;
            modelGradient += weight * g + value * slope;
            weightGradient += slope;
        }
    }

    // The hit's gradient, exactly: the models' would carry their value
    // errors times the weights' slopes (degrees off on the hand).
    CellTraceResult hitAt(CellTraceResult r, const ModelledPart& part, const Vec3& o, const Vec3& d) const {
        Vec3 gradient;
        field_->valueAndGradient(o + r.t * d, gradient,
                                 std::span<const uint32_t>(localIndices_.data() + part.first, part.count));
        r.evaluations += field_->termCount();
        if (gradient.allFinite() && gradient.squaredNorm() > 0) {
            r.gradientKnown = true;
            r.gradient = worldGradient(placement_, gradient);
        }
        return r;
    }

    std::shared_ptr<const MpuField> field_;
    LeafPlacement placement_;
    std::vector<ModelledPart> parts_;
    std::vector<ModelledLocal> locals_;     ///< each part's interpolants, parts_[i].first onwards
    std::vector<uint32_t> localIndices_;    ///< the same as indices into the field's locals
    std::vector<VariationalPatch> models_;  ///< their models over the part, in the same order
    double background_;                     ///< the background's share of N inside the domain
};

// Whether N can vanish in the box: each model's range over it (error
// included) weighted by the range of its weight there. Tighter than the
// field's own range, which spans every interpolant's interval bound.
bool mayHoldSurface(const MpuField& field, const Box3& box, const std::vector<uint32_t>& touching,
                    const std::vector<VariationalPatch>& models) {
    const double background = MpuField::kBackgroundWeight * field.backgroundMargin();
    double lo = background, hi = background;
    for (size_t k = 0; k < touching.size(); ++k) {
        const MpuLocal& l = field.locals()[touching[k]];
        const Interval distance = box.distanceRange(l.center);
        const double radius2 = l.radius * l.radius;
        const double least = mpuWeight(distance.hi * distance.hi, radius2), most = mpuWeight(distance.lo * distance.lo, radius2);
        const Interval& range = models[k].range;
        lo += range.lo * (range.lo >= 0 ? least : most);
        hi += range.hi * (range.hi >= 0 ? most : least);
    }
    return lo <= 0 && hi >= 0;
}

}  // namespace

std::optional<CellAcceleration> PartitionedVariationalCellAccelerator::accelerate(const FieldProgram& program,
                                                                                  const Box3& box,
                                                                                  double surfaceDiagonal) const {
    const FieldLeaf* leaf = program.singleLeaf();
    const auto* mpu = leaf ? std::get_if<MpuLeafField>(&leaf->shape) : nullptr;
    if (!mpu || !mpu->field->hasInterpolants()) return std::nullopt;
    const MpuField& field = *mpu->field;
    const LeafPlacement& placement = leaf->placement;
    const Box3 leafBox = placement.leafFromWorld(box);
    // Beyond the domain the background term is a distance, not a constant.
    if (!field.bounds().contains(leafBox)) return std::nullopt;
    const double tolerance = kRelativeTolerance * surfaceDiagonal / placement.valueScale;

    std::vector<ModelledPart> parts;
    std::vector<ModelledLocal> locals;
    std::vector<uint32_t> localIndices;
    std::vector<VariationalPatch> models;
    std::vector<uint32_t> touching;
    bool declined = false;
    auto carve = [&](auto&& self, const Box3& b, int splits) -> void {
        if (declined || !field.range(b).containsZero()) return;
        field.localsTouching(b, touching);
        if (touching.empty()) return;  // the background alone: positive
        const bool crowded = touching.size() > kMaxLocals;
        std::vector<VariationalPatch> partModels;
        double worst = 0.0;
        size_t nearTerms = 0, allTerms = 0;
        if (!crowded) {
            for (const uint32_t i : touching) {
                const MpuLocal& l = field.locals()[i];
                // Quadric locals (MPU fits) are mpu_cells' work.
                std::optional<VariationalPatch> model;
                if (l.combination == MpuCombination::Interpolant)
                    model = buildVariationalPatch(field.interpolants()[l.first], b);
                if (!model) {
                    declined = true;
                    return;
                }
                worst = std::max(worst, model->valueError);
                nearTerms += model->nearTermCount();
                allTerms += field.interpolants()[l.first].termCount();
                partModels.push_back(std::move(*model));
            }
        }
        if ((crowded || worst > tolerance) && splits < kMaxSplits) {
            for (int k = 0; k < 8; ++k) self(self, b.octant(k), splits + 1);
            return;
        }
        if (crowded || double(nearTerms) > kMostNearShare * double(allTerms)) {
            declined = true;
            return;
        }
        if (!mayHoldSurface(field, b, touching, partModels)) return;
        ModelledPart part{b, uint32_t(locals.size()), uint32_t(touching.size())};
        for (size_t k = 0; k < touching.size(); ++k) {
            const MpuLocal& l = field.locals()[touching[k]];
            const VariationalPatch& m = partModels[k];
            locals.push_back({l.center, l.radius, 1.0 / (l.radius * l.radius), m.valueError, m.lipschitz,
                              m.evaluationNoise});
            localIndices.push_back(touching[k]);
            part.errorSlope += kMpuWeightSlope / l.radius * m.valueError + m.gradientError;
            part.errorCurvature += kWeightCurvature / (l.radius * l.radius) * m.valueError +
                                   2.0 * kMpuWeightSlope / l.radius * m.gradientError + m.hessianError;
            models.push_back(std::move(partModels[k]));
        }
        parts.push_back(part);
    };
    carve(carve, leafBox, 0);
    if (declined) return std::nullopt;

    CellAcceleration a;
    std::vector<Box3> boxes;
    for (const ModelledPart& part : parts) boxes.push_back(part.box);
    a.parts = worldPartBoxes(placement, boxes, box);
    a.tracer = std::make_unique<PartitionedVariationalCellTracer>(mpu->field, placement, std::move(parts),
                                                                  std::move(locals), std::move(localIndices),
                                                                  std::move(models));
    return a;
}

}  // namespace isotrace::geometry
