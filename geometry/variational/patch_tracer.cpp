#include "geometry/variational/patch_tracer.h"

#include "geometry/bracketed_root.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {

inline int signOf(double v) { return (v > 0) - (v < 0); }

// The first root after 0 of a + b x - c x^2 (a > 0, c >= 0): how far a
// value of at least a, moving with slope at least b and curving by at most
// 2c, surely keeps its sign. Infinite when it never falls to 0.
inline double parabolaReach(double a, double b, double c) {
    if (!(a > 0)) return 0.0;
    const double root = std::sqrt(b * b + 4.0 * a * c);
    if (b < 0) return 2.0 * a / (root - b);  // the stable form
    return c > 0 ? (b + root) / (2.0 * c) : std::numeric_limits<double>::infinity();
}

// What one exact evaluation says about f near it: e = f - model is known
// there, with its slope along the ray, and the model's gradient and Hessian
// errors bound how fast that knowledge fades with distance.
struct Anchor {
    bool made = false;
    double t = 0, value = 0;
    double offset = 0, offsetSlope = 0;  // e and de/dt at the anchor
    Vec3 gradient = Vec3::Zero();        // exact grad f at the anchor

    // Raises (sign, margin) to what the anchor proves about f at t, where
    // the model's value is `model`.
    void certify(const VariationalPatch& patch, double t, double model, double speed, int& sign,
                 double& margin) const {
        const double dt = t - this->t, noise = patch.evaluationNoise;
        const double firstOrder = model + offset, firstDrift = patch.gradientError * speed * std::abs(dt) + noise;
        const double secondOrder = firstOrder + offsetSlope * dt,
                     secondDrift = 0.5 * patch.hessianError * speed * speed * dt * dt + noise;
        if (std::abs(firstOrder) - firstDrift > margin) {
            sign = signOf(firstOrder);
            margin = std::abs(firstOrder) - firstDrift;
        }
        if (std::abs(secondOrder) - secondDrift > margin) {
            sign = signOf(secondOrder);
            margin = std::abs(secondOrder) - secondDrift;
        }
    }
};

}  // namespace

PatchTraceResult tracePatch(const VariationalPatch& patch, const VariationalField& field, const Vec3& origin,
                            const Vec3& direction, double tStart, double tEnd, double minStep, bool anyHit,
                            int maxSteps) {
    PatchTraceResult result;
    const double speed = direction.norm();
    if (!(speed > 0) || !(tEnd >= tStart) || patch.holdsNoZero) return result;

    int side = 0;              // sign of f on the part of the ray already cleared
    double tCleared = tStart;  // the last point known to have that sign
    double fCleared = std::numeric_limits<double>::quiet_NaN();  // exact f there, when known
    Anchor anchor;
    auto exactAt = [&](double t, Vec3* gradient) {
        ++result.exactEvaluations;
        if (gradient) return field.valueAndGradient(origin + t * direction, *gradient);
        return field.value(origin + t * direction);
    };
    auto anchorAt = [&](double t, const Vec3& p) {
        anchor.value = exactAt(t, &anchor.gradient);
        double modelSlope;
        const double model = patch.valueAndSlope(p, direction, modelSlope);
        anchor.made = true;
        anchor.t = t;
        anchor.offset = anchor.value - model;
        anchor.offsetSlope = anchor.gradient.dot(direction) - modelSlope;
    };
    auto hitAt = [&](double t, const Vec3& gradient) {
        result.hit = true;
        result.t = t;
        result.gradient = gradient;
        return result;
    };
    // Any-hit: f has the sign `side` where the ray was last cleared; if the
    // model proves the other sign at some t in the segment, a root lies
    // between. The hit is reported halfway (strictly inside the segment),
    // with the model's gradient there for a normal.
    auto anyHitAt = [&](double t) {
        const double between = 0.5 * (tCleared + t);
        Vec3 gradient;
        patch.valueAndGradient(origin + between * direction, gradient);
        return hitAt(between, gradient);
    };
    // A sign change at an anchor at t: Newton from it, when the bound on
    // f'' along the bracket [tCleared, t] puts its root within a thousandth
    // of minStep of f's; NaN when not.
    auto newtonFromAnchor = [&](double t, double curvature) {
        const double slope = anchor.gradient.dot(direction), width = t - tCleared;
        const double leastSlope = std::abs(slope) - curvature * width;
        if (!(t == anchor.t && leastSlope > 0 && 0.5 * curvature * width * width <= 1e-3 * minStep * leastSlope))
            return std::numeric_limits<double>::quiet_NaN();
        return std::clamp(anchor.t - anchor.value / slope, tCleared, t);
    };
    // A sign change after a forced step: the bracket [tCleared, t] has ends
    // of opposite signs; settle it with exact values.
    auto refineBracket = [&](double t) {
        const double fa = std::isnan(fCleared) ? exactAt(tCleared, nullptr) : fCleared;
        const double fb = exactAt(t, nullptr);
        if (signOf(fa) == signOf(fb)) return std::numeric_limits<double>::quiet_NaN();  // rounding; go on
        const double root = bracketedRoot([&](double u) { return field.value(origin + u * direction); }, tCleared, fa,
                                          t, fb, 1e-3 * minStep, &result.exactEvaluations);
        exactAt(root, &result.gradient);
        return root;
    };

    const double stepScale = 1.0 / (patch.lipschitz * speed);
    // Along the ray the model curves by at most this; so does e = f - model
    // by the Hessian error.
    const double modelCurvature = patch.curvature * speed * speed,
                 errorCurvature = patch.hessianError * speed * speed, slopeNoise = patch.gradientNoise * speed;

    // A closest hit by the model alone, tried where the first anchor would
    // be made at t: near the expansion point the model's error falls as the
    // fifth power of the distance, and where it is below the model's
    // margins the model proves f keeps its sign on [t, root - minStep / 2]
    // and has the other at root + minStep / 2. The hit is then reported at
    // the model's root with the model's gradient (when that is within a
    // thousandth of it), and f is not evaluated: most hits cost an exact
    // O(N) sum otherwise. NaN where the model cannot prove it.
    auto modelOnlyRoot = [&](double t, double model, double modelSlope) {
        constexpr double none = std::numeric_limits<double>::quiet_NaN();
        constexpr int kNewtonSteps = 4, kSignSteps = 8;
        double root = t, m = model, slope = modelSlope;
        for (int k = 0; k < kNewtonSteps; ++k) {
            if (!(slope != 0)) return none;
            root -= m / slope;
            if (!(root >= t && root + 0.5 * minStep <= tEnd)) return none;
            m = patch.valueAndSlope(origin + root * direction, direction, slope);
            ++result.steps;
        }
        const double before = root - 0.5 * minStep, after = root + 0.5 * minStep;
        // The segment [t, after] lies within this of the expansion point
        // (a ball is convex: its farthest point is an end).
        const double reach = std::max((origin + t * direction - patch.expansionPoint).norm(),
                                      (origin + after * direction - patch.expansionPoint).norm());
        const double error = patch.valueErrorWithin(reach);
        const int sign = side != 0 ? side : signOf(model);
        ++result.steps;
        const double mAfter = patch.value(origin + after * direction);
        if (!(std::abs(mAfter) > error && signOf(mAfter) == -sign)) return none;
        // [t, before]: parabola steps below sign * model - error.
        double u = t, mu = model, su = modelSlope;
        for (int k = 0; k < kSignSteps; ++k) {
            if (!(signOf(mu) == sign && std::abs(mu) > error)) return none;
            u += parabolaReach(std::abs(mu) - error, sign * su - slopeNoise, 0.5 * modelCurvature);
            if (u >= before) return root;
            mu = patch.valueAndSlope(origin + u * direction, direction, su);
            ++result.steps;
        }
        return none;
    };
    auto modelOnlyHit = [&](double root) {
        Vec3 gradient;
        patch.valueAndGradient(origin + root * direction, gradient);
        const double reach = (origin + root * direction - patch.expansionPoint).norm();
        if (!(patch.gradientErrorWithin(reach) <= 1e-3 * gradient.norm())) return false;
        hitAt(root, gradient);
        result.modelHit = true;
        return true;
    };
    auto tryModelOnlyHit = [&](double t, double model, double modelSlope) {
        if (anyHit) return false;
        const double root = modelOnlyRoot(t, model, modelSlope);
        return !std::isnan(root) && modelOnlyHit(root);
    };
    double t = tStart;
    while (t <= tEnd) {
        if (++result.steps > maxSteps) {
            result.complete = false;
            result.t = t;
            return result;
        }
        const Vec3 p = origin + t * direction;
        double modelSlope;
        const double model = patch.valueAndSlope(p, direction, modelSlope);
        const bool atAnchor = anchor.made && t == anchor.t;
        // The sign f certainly has here, and how far |f| is from 0.
        int sign = 0;
        double margin = 0.0;
        if (atAnchor) {
            sign = signOf(anchor.value);
            margin = std::abs(anchor.value);
            if (sign == 0) return hitAt(t, anchor.gradient);  // f == 0 exactly
        } else {
            if (std::abs(model) > patch.valueError) {
                sign = signOf(model);
                margin = std::abs(model) - patch.valueError;
            }
            if (anchor.made) anchor.certify(patch, t, model, speed, sign, margin);
        }
        // Uncertain without an anchor: make one where the model puts the
        // root, if that lies ahead within the segment (the model is usually
        // far better than its bound, so the anchor lands next to the hit
        // and certifies the rest of the way), else here.
        auto modelRoot = [&] { return model * modelSlope < 0 ? std::min(t - model / modelSlope, tEnd) : t; };
        // Where an anchor would be made, an occlusion query first asks the
        // model a little past its root, far enough that the value error
        // cannot hide the other sign: where it proves it, or NaN.
        auto crossingAhead = [&] {
            constexpr double none = std::numeric_limits<double>::quiet_NaN();
            if (!anyHit || side == 0 || !(model * modelSlope < 0) || signOf(model) != side) return none;
            const double beyond = t - model / modelSlope + 2.0 * patch.valueError / std::abs(modelSlope);
            if (!(beyond > tCleared && beyond <= tEnd)) return none;
            ++result.steps;
            const double there = patch.value(origin + beyond * direction);
            return std::abs(there) > patch.valueError && signOf(there) == -side ? beyond : none;
        };
        if (sign == 0 && !anchor.made) {
            if (const double beyond = crossingAhead(); !std::isnan(beyond)) return anyHitAt(beyond);
            if (tryModelOnlyHit(t, model, modelSlope)) return result;
            const double tAnchor = modelRoot();
            anchorAt(tAnchor, origin + tAnchor * direction);
            continue;
        }
        // Uncertain with one: within the anchor's drift of the surface, and
        // if that is within resolution, a forced step below; else (or while
        // no sign is known yet) an anchor here.
        if (sign == 0 && !atAnchor) {
            const double away = t - anchor.t;
            const double drift = 0.5 * errorCurvature * away * away + patch.evaluationNoise;
            if (side == 0 || drift > minStep * std::abs(modelSlope + anchor.offsetSlope)) {
                anchorAt(t, p);
                continue;
            }
        }
        if (sign != 0 && side == 0) side = sign;
        else if (sign != 0 && sign != side) {
            if (anyHit) return anyHitAt(t);
            const double newton = newtonFromAnchor(t, modelCurvature + errorCurvature);
            if (!std::isnan(newton)) return hitAt(newton, anchor.gradient);
            const double root = refineBracket(t);
            if (!std::isnan(root)) return hitAt(root, result.gradient);
            side = sign;
        }
        // The step: |f| >= margin - L |dx| > 0 within margin / L; or, from
        // the model's value and slope, the parabola below sign * f (the
        // model's curvature, and the error's bound: e within the value
        // error, or its drift from the anchor).
        double step = margin * stepScale;
        const double ownSlope = sign * modelSlope - slopeNoise;
        if (sign != 0 && std::abs(model) > patch.valueError && signOf(model) == sign)
            step = std::max(step, parabolaReach(std::abs(model) - patch.valueError, ownSlope, 0.5 * modelCurvature));
        if (sign != 0 && anchor.made) {
            const double away = t - anchor.t;
            const double a = sign * (model + anchor.offset + anchor.offsetSlope * away) - patch.evaluationNoise -
                             0.5 * errorCurvature * away * away;
            const double b = ownSlope + sign * anchor.offsetSlope - errorCurvature * away;
            step = std::max(step, parabolaReach(a, b, 0.5 * (modelCurvature + errorCurvature)));
        }
        if (step >= minStep) {
            // No root within `step`: |f| >= margin - L |dx| > 0.
            tCleared = t;
            fCleared = atAnchor ? anchor.value : std::numeric_limits<double>::quiet_NaN();
            if (t + step >= tEnd) return result;
            t += step;
            continue;
        }
        // Stalled within resolution of the surface (or grazing it): a
        // forced step of minStep, which may skip a sliver thinner than that,
        // as the general sphere tracer's does. The anchor (made here if there
        // is none) tells the sign at its end.
        if (!anchor.made) {
            if (const double beyond = crossingAhead(); !std::isnan(beyond)) return anyHitAt(beyond);
            if (tryModelOnlyHit(t, model, modelSlope)) return result;
            const double tAnchor = modelRoot();
            anchorAt(tAnchor, origin + tAnchor * direction);
            continue;
        }
        const double tForced = std::min(t + minStep, tEnd);
        tCleared = t;
        fCleared = atAnchor ? anchor.value : std::numeric_limits<double>::quiet_NaN();
        const Vec3 q = origin + tForced * direction;
        const double forcedModel = patch.value(q);
        int forcedSign = 0;
        double forcedMargin = 0.0;
        if (std::abs(forcedModel) > patch.valueError) {
            forcedSign = signOf(forcedModel);
            forcedMargin = std::abs(forcedModel) - patch.valueError;
        }
        anchor.certify(patch, tForced, forcedModel, speed, forcedSign, forcedMargin);
        if (forcedSign == -side) {
            // The root is in [t, tForced]: Newton from the anchor
            // (quadratic, the anchor is within resolution of it).
            const double slope = anchor.gradient.dot(direction);
            const double tNewton = slope != 0 ? anchor.t - anchor.value / slope : t;
            return hitAt(std::clamp(tNewton, t, tForced), anchor.gradient);
        }
        if (forcedSign == side && tForced >= tEnd) return result;
        t = tForced;
        if (forcedSign == 0) anchorAt(t, q);
    }
    return result;
}

}  // namespace isotrace::geometry
