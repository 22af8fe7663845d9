#include "geometry/tracing/variational_csg_cells.h"

#include <algorithm>
#include <cmath>

#include "geometry/bracketed_root.h"
#include "geometry/variational/variational_patch.h"

namespace isotrace::geometry {

namespace {

// Models' value error over the diagonal of the surface: the model certifies
// signs down to about this distance from it (in value), the exact tree the rest.
constexpr double kRelativeTolerance = 1e-3;
constexpr int kFinestSplit = 2;

class VariationalCsgCellTracer final : public CellTracer {
public:
    // Its models are proven over its parts only.
    bool tracesFromBeforeItsPart() const override { return false; }

    VariationalCsgCellTracer(FieldProgram program, uint32_t leaf, const Box3& leafBox, int split,
                             std::vector<VariationalPatch> models, double lipschitz, size_t terms)
        : program_(std::move(program)), leaf_(leaf), placement_(program_.leaf(leaf).placement),
          field_(std::get<VariationalLeafField>(program_.leaf(leaf).shape).field.get()), leafBox_(leafBox),
          split_(split), models_(std::move(models)), lipschitz_(lipschitz), terms_(terms) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        const double speed = direction.norm();
        if (!(speed > 0) || !(t1 >= t0)) return r;
        const double minStep = settings.epsilon / speed, stepScale = 1.0 / (std::max(lipschitz_, 1e-300) * speed);
        // The ray in the leaf's frame (an affine map keeps t).
        Vec3 leafOrigin, leafDirection;
        rayInLeafFrame(placement_, origin, direction, leafOrigin, leafDirection);
        const double leafSpeed = leafDirection.norm();
        int exactSteps = 0;
        auto finish = [&](bool hit, double t) {
            r.hit = hit;
            r.t = t;
            r.evaluations = uint64_t(r.steps) * VariationalPatch::kMonomials + uint64_t(exactSteps) * terms_;
            r.steps += exactSteps;
            return r;
        };
        // One exact evaluation of the leaf (value and gradient) corrects its
        // model near it: e = f - model is known there with its slope along
        // the ray, and the model's gradient and Hessian errors bound how fast
        // that knowledge fades. Valid within the anchor's own model.
        struct Anchor {
            const VariationalPatch* patch = nullptr;
            double t = 0, offset = 0, offsetSlope = 0;
        } anchor;
        // The leaf's value at t lies in [lo, hi]; its best estimate is `centre`.
        auto leafInterval = [&](double t, const VariationalPatch& patch, double& lo, double& hi, double& centre) {
            const double model = patch.value(leafOrigin + t * leafDirection);
            lo = model - patch.valueError;
            hi = model + patch.valueError;
            centre = model;
            if (anchor.patch != &patch) return;
            const double dt = t - anchor.t, noise = patch.evaluationNoise;
            const double first = model + anchor.offset, firstDrift = patch.gradientError * leafSpeed * std::abs(dt) + noise;
            const double second = first + anchor.offsetSlope * dt,
                         secondDrift = 0.5 * patch.hessianError * leafSpeed * leafSpeed * dt * dt + noise;
            lo = std::max({lo, first - firstDrift, second - secondDrift});
            hi = std::min({hi, first + firstDrift, second + secondDrift});
            centre = second;
        };
        auto anchorAt = [&](double t, const VariationalPatch& patch) {
            const Vec3 q = leafOrigin + t * leafDirection;
            Vec3 gradient, modelGradient;
            const double exact = field_->valueAndGradient(q, gradient);
            ++exactSteps;
            const double model = patch.valueAndGradient(q, modelGradient);
            anchor = {&patch, t, exact - model, (gradient - modelGradient).dot(leafDirection)};
        };
        // The tree's value with the leaf at `leafValue` (leaf units).
        auto tree = [&](double t, double leafValue) {
            return program_.valueWithLeafValue(origin + t * direction, leaf_, placement_.valueScale * leafValue);
        };

        int previousSign = 0;
        double tPrevious = t0;
        double t = t0;
        while (r.steps + exactSteps < settings.maxSteps) {
            const VariationalPatch& patch = modelAt(leafOrigin + t * leafDirection);
            double lo, hi, centre;
            leafInterval(t, patch, lo, hi, centre);
            double a = tree(t, lo), b = tree(t, hi);
            ++r.steps;
            if (std::min(a, b) <= 0 && std::max(a, b) >= 0 && !(anchor.patch == &patch && anchor.t == t)) {
                // Not certain: anchor here and ask again (exactly, at the anchor).
                anchorAt(t, patch);
                leafInterval(t, patch, lo, hi, centre);
                a = tree(t, lo);
                b = tree(t, hi);
            }
            int sign = 0;
            double margin = 0.0;
            if (std::min(a, b) > 0) {
                sign = 1, margin = std::min(a, b);
            } else if (std::max(a, b) < 0) {
                sign = -1, margin = -std::max(a, b);
            } else {
                // Within rounding of the surface at the anchor: the best estimate's sign.
                const double estimate = tree(t, centre);
                if (estimate == 0.0) return finish(true, t);
                sign = estimate < 0 ? -1 : 1;
            }
            if (previousSign != 0 && sign != previousSign) {
                // The root is in [tPrevious, t]: on the anchored model where
                // the anchor reaches (its drift over a step is far below the
                // resolution), else on the exact tree.
                int evaluations = 0;
                auto corrected = [&](double u) {
                    double l, h, c;
                    leafInterval(u, patch, l, h, c);
                    return tree(u, c);
                };
                double root = NAN;
                if (&modelAt(leafOrigin + tPrevious * leafDirection) == &patch) {
                    // The anchored model's drift over the bracket, as a
                    // distance along the ray, must be far below resolution:
                    // else anchor again at t, next to the root.
                    auto settle = [&] {
                        if (anchor.patch != &patch) return false;
                        const double dt = std::max(std::abs(t - anchor.t), std::abs(tPrevious - anchor.t));
                        const double drift =
                            placement_.valueScale * (0.5 * patch.hessianError * leafSpeed * leafSpeed * dt * dt +
                                                     patch.evaluationNoise);
                        const double fa = corrected(tPrevious), fb = corrected(t);
                        const double slope = std::abs(fb - fa) / std::max(t - tPrevious, 1e-300);
                        if ((fa < 0) == (fb < 0) || drift > 1e-2 * minStep * slope) return false;
                        root = bracketedRoot(corrected, tPrevious, fa, t, fb, 1e-3 * minStep, &evaluations);
                        r.steps += evaluations + 2;
                        return true;
                    };
                    if (!settle() && !(anchor.patch == &patch && anchor.t == t)) {
                        anchorAt(t, patch);
                        settle();
                    }
                }
                if (std::isnan(root)) {
                    const double fa = program_.value(origin + tPrevious * direction);
                    const double fb = program_.value(origin + t * direction);
                    exactSteps += 2;
                    if ((fa < 0) == (fb < 0)) {
                        previousSign = 0;  // rounding: start afresh from here
                        continue;
                    }
                    root = refineRoot(program_, origin, direction, tPrevious, fa, t, fb, 1e-3 * minStep, &evaluations);
                    exactSteps += evaluations;
                }
                return finish(true, root);
            }
            previousSign = sign;
            tPrevious = t;
            if (t >= t1) return finish(false, 0.0);
            const double step = margin * stepScale;
            if (step >= minStep && t + step >= t1) return finish(false, 0.0);  // no zero up to the end
            // A forced step of minStep may skip a sliver thinner than that, as
            // the general tracer's does.
            t = std::min(t + std::max(step, minStep), t1);
        }
        // Out of steps (a ray grazing the surface): the exact tree settles the
        // rest from the last point whose sign is known, with the models'
        // gradient bound rather than the cell's interval one (often tens of
        // times larger).
        const TraceResult rest = sphereTrace(program_, lipschitz_, origin, direction, tPrevious, t1, settings);
        exactSteps += rest.steps;
        return finish(rest.hit, rest.t);
    }

private:
    // The model whose box holds q (a point of the part, in the leaf's frame).
    const VariationalPatch& modelAt(const Vec3& q) const {
        if (split_ == 1) return models_[0];
        int index = 0;
        for (int axis = 2; axis >= 0; --axis) {
            const double u = (q[axis] - leafBox_.lower[axis]) / (leafBox_.upper[axis] - leafBox_.lower[axis]);
            index = index * split_ + std::clamp(int(u * split_), 0, split_ - 1);
        }
        return models_[size_t(index)];
    }

    FieldProgram program_;
    uint32_t leaf_;
    LeafPlacement placement_;
    const VariationalField* field_;  ///< the leaf's, owned by program_
    Box3 leafBox_;  ///< the part in the leaf's frame, split into split^3 boxes with a model each
    int split_;
    std::vector<VariationalPatch> models_;  ///< of the variational leaf, in its frame, x fastest
    double lipschitz_;  ///< of the tree over the part
    size_t terms_;      ///< of the variational leaf: the cost of an exact evaluation
};

}  // namespace

std::optional<CellAcceleration> VariationalCsgCellAccelerator::accelerate(const FieldProgram& program,
                                                                          const Box3& box,
                                                                          double surfaceDiagonal) const {
    // One variational leaf among other leaves (a bare one is variational_cells').
    int leaves = 0, variationalLeaves = 0;
    uint32_t leaf = 0;
    for (const FieldInstruction& in : program.instructions()) {
        if (in.op != FieldOp::Leaf) continue;
        ++leaves;
        if (std::holds_alternative<VariationalLeafField>(program.leaf(in.a).shape)) {
            ++variationalLeaves;
            leaf = in.a;
        }
    }
    if (variationalLeaves != 1 || leaves < 2) return std::nullopt;
    const FieldLeaf& variational = program.leaf(leaf);
    const VariationalField& field = *std::get<VariationalLeafField>(variational.shape).field;
    CellAcceleration a;
    const Box3 part = shrunkToSurface(box, [&](const Box3& b) { return program.range(b); });
    if (part.isEmpty()) return a;
    const LeafPlacement& placement = variational.placement;
    const Box3 leafBox = placement.identity ? part : transformBox(placement.linear, placement.offset, part);
    // Models fine enough to certify signs away from the surface: a model per
    // box of a split x split x split grid, the coarsest that meets the
    // tolerance (or the finest tried).
    const double tolerance = kRelativeTolerance * surfaceDiagonal / placement.valueScale;
    std::vector<VariationalPatch> models;
    int split = 1;
    for (;; split *= 2) {
        models.clear();
        double worst = 0.0;
        const Vec3 size = leafBox.extent() / double(split);
        for (int z = 0; z < split; ++z)
            for (int y = 0; y < split; ++y)
                for (int x = 0; x < split; ++x) {
                    const Vec3 lower = leafBox.lower + size.cwiseProduct(Vec3(x, y, z));
                    std::optional<VariationalPatch> model = buildVariationalPatch(field, Box3(lower, lower + size));
                    if (!model) return std::nullopt;
                    worst = std::max(worst, model->valueError);
                    models.push_back(std::move(*model));
                }
        if (worst <= tolerance || split == kFinestSplit) break;
    }
    // The tree's gradient is a convex combination of its leaves' (min, max,
    // the polynomial smooth min, negation, offsets), so the largest leaf
    // bound bounds it; the models bound the variational leaf's far more
    // tightly than interval sums over the part do.
    double lipschitz = 0.0;
    for (const VariationalPatch& model : models) lipschitz = std::max(lipschitz, placement.gradientScale * model.lipschitz);
    for (const FieldInstruction& in : program.instructions()) {
        if (in.op != FieldOp::Leaf || in.a == leaf) continue;
        const FieldLeaf& other = program.leaf(in.a);
        const Box3 otherBox =
            other.placement.identity ? part : transformBox(other.placement.linear, other.placement.offset, part);
        lipschitz = std::max(lipschitz, other.placement.gradientScale *
                                            std::visit([&](const auto& s) { return s.lipschitz(otherBox); }, other.shape));
    }
    a.parts = {part};
    a.tracer = std::make_unique<VariationalCsgCellTracer>(program, leaf, leafBox, split, std::move(models),
                                                          lipschitz * (1.0 + 1e-12), field.termCount());
    return a;
}

}  // namespace isotrace::geometry
