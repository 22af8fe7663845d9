#include "geometry/tracing/sphere_tracer.h"

#include "geometry/bracketed_root.h"

#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {
inline bool differentSigns(double a, double b) { return (a < 0) != (b < 0); }
}  // namespace

bool clipRayToBox(const Box3& box, const Vec3& origin, const Vec3& direction, double& tEnter, double& tExit) {
    for (int axis = 0; axis < 3; ++axis) {
        const double inv = 1.0 / direction[axis];
        double t0 = (box.lower[axis] - origin[axis]) * inv;
        double t1 = (box.upper[axis] - origin[axis]) * inv;
        if (std::isnan(t0) || std::isnan(t1)) {  // parallel ray on a slab plane
            if (origin[axis] < box.lower[axis] || origin[axis] > box.upper[axis]) return false;
            continue;
        }
        if (t0 > t1) std::swap(t0, t1);
        tEnter = std::max(tEnter, t0);
        tExit = std::min(tExit, t1);
    }
    return tEnter <= tExit;
}

double refineRoot(const FieldProgram& field, const Vec3& origin, const Vec3& direction, double ta, double fa,
                  double tb, double fb, double tolerance, int* evaluations) {
    return bracketedRoot([&](double t) { return field.value(origin + t * direction); }, ta, fa, tb, fb, tolerance,
                         evaluations);
}

TraceResult sphereTrace(const FieldProgram& field, double lipschitz, const Vec3& origin, const Vec3& direction,
                        double tStart, double tEnd, const TraceSettings& settings) {
    TraceResult result;
    const double speed = direction.norm();
    if (!(speed > 0) || !(tEnd >= tStart)) return result;
    const double minStep = settings.epsilon / speed;
    const double stepScale = 1.0 / (std::max(lipschitz, 1e-300) * speed);
    const double tolerance = 1e-3 * minStep;
    const uint64_t cost = field.evaluationCost();

    double t = tStart;
    double safe = 0.0;  // a radius free of zeros, from fields that can say
    double f = field.valueAndSafeDistance(origin + t * direction, safe);
    int steps = 1;
    auto finish = [&](bool hit, double tHit) {
        result.hit = hit;
        result.t = tHit;
        result.steps = steps;
        result.evaluations = static_cast<uint64_t>(steps) * cost;
        return result;
    };
    // At a zero tZero with value `before` just ahead of it: true when the
    // field crosses there. A zero with the same sign on both sides is
    // touched, not crossed (a ray through a concave edge of a CSG solid, or
    // tangent to a surface, stays on its side): the march then goes on a
    // resolution step past it.
    auto crossesAt = [&](double before, double tZero) {
        double safeAfter = 0.0;
        const double after = field.valueAndSafeDistance(origin + (tZero + minStep) * direction, safeAfter);
        ++steps;
        if (before == 0.0 || after == 0.0 || differentSigns(before, after)) return true;
        t = tZero + minStep;
        f = after;
        safe = safeAfter;
        return false;
    };
    if (f == 0.0) {
        // Starting on a zero: the cell's bounds hold a resolution step
        // around its segment, so the value before it can be asked.
        double unused = 0.0;
        const double before = field.valueAndSafeDistance(origin + (t - minStep) * direction, unused);
        ++steps;
        if (crossesAt(before, t)) return finish(true, t);
        if (t >= tEnd) return finish(false, 0.0);
    }

    // Over-relaxed steps (Keinert et al. 2014) go omega times past the ball
    // proven free of zeros around t. The step stands only when the ball
    // around its end overlaps that one, so the two balls cover the segment
    // and every step is still proven; otherwise the plain step is taken
    // (one evaluation lost) and relaxation stays off for this march, as the
    // surface is near.
    double omega = settings.overRelaxation;
    // The ray parameter span around a point that holds no zero.
    auto provenRadius = [&](double value, double safeDistance) {
        return std::max(std::abs(value) * stepScale, safeDistance / speed);
    };
    while (steps < settings.maxSteps) {
        const double radius = provenRadius(f, safe);
        const bool forced = radius < minStep;  // a forced step may skip a sliver thinner than epsilon
        if (!forced && t + radius >= tEnd) return finish(false, 0.0);  // the ball reaches past tEnd
        double tNext = std::min(t + (forced ? minStep : omega * radius), tEnd);
        double safeNext = 0.0;
        double fNext = field.valueAndSafeDistance(origin + tNext * direction, safeNext);
        ++steps;
        if (!forced && tNext - t > radius) {
            if (fNext == 0.0 || differentSigns(f, fNext) || radius + provenRadius(fNext, safeNext) <= tNext - t) {
                tNext = t + radius;
                fNext = field.valueAndSafeDistance(origin + tNext * direction, safeNext);
                ++steps;
                omega = 1.0;
            }
        }
        if (fNext == 0.0) {
            if (crossesAt(f, tNext)) return finish(true, tNext);
            if (t >= tEnd) return finish(false, 0.0);
            continue;
        }
        if (differentSigns(f, fNext)) {
            // An occlusion query needs no more than the bracket.
            if (settings.anyHit) return finish(true, 0.5 * (t + tNext));
            const double root = refineRoot(field, origin, direction, t, f, tNext, fNext, tolerance, &steps);
            return finish(true, root);
        }
        if (tNext >= tEnd) return finish(false, 0.0);
        t = tNext;
        f = fNext;
        safe = safeNext;
    }
    // Out of steps (a ray grazing the surface for a long way): settle the
    // rest of the segment with the robust method rather than guess.
    TraceResult rest = intervalBisectionTrace(field, origin, direction, t, tEnd, settings);
    rest.steps += steps;
    rest.evaluations += static_cast<uint64_t>(steps) * cost;
    return rest;
}

namespace {

struct BisectionState {
    const FieldProgram& field;
    const Vec3& origin;
    const Vec3& direction;
    double speed;
    double epsilon;
    int evaluations = 0;
    int budget = 1 << 20;
};

// First sign change in [t0, t1] with known end values, or NaN.
double bisect(BisectionState& s, double t0, double f0, double t1, double f1) {
    if (s.evaluations > s.budget) return std::numeric_limits<double>::quiet_NaN();
    const double length = (t1 - t0) * s.speed;
    if (length <= s.epsilon) {
        if (differentSigns(f0, f1) || f1 == 0.0)
            return refineRoot(s.field, s.origin, s.direction, t0, f0, t1, f1, 1e-3 * s.epsilon / s.speed,
                              &s.evaluations);
        return std::numeric_limits<double>::quiet_NaN();
    }
    Box3 box;
    box.extend(s.origin + t0 * s.direction);
    box.extend(s.origin + t1 * s.direction);
    const BoxEstimate e = s.field.estimate(box);
    ++s.evaluations;
    if (!e.range.containsZero()) return std::numeric_limits<double>::quiet_NaN();
    // Along the segment, f stays within L * distance of either end.
    if (std::min(std::abs(f0), std::abs(f1)) > 0 && !differentSigns(f0, f1) &&
        std::abs(f0) + std::abs(f1) > e.lipschitz * length)
        return std::numeric_limits<double>::quiet_NaN();
    const double tm = 0.5 * (t0 + t1);
    const double fm = s.field.value(s.origin + tm * s.direction);
    ++s.evaluations;
    const double left = bisect(s, t0, f0, tm, fm);
    if (!std::isnan(left)) return left;
    return bisect(s, tm, fm, t1, f1);
}

}  // namespace

TraceResult intervalBisectionTrace(const FieldProgram& field, const Vec3& origin, const Vec3& direction,
                                   double tStart, double tEnd, const TraceSettings& settings) {
    TraceResult result;
    const double speed = direction.norm();
    if (!(speed > 0) || !(tEnd >= tStart)) return result;
    BisectionState state{field, origin, direction, speed, settings.epsilon};
    const double f0 = field.value(origin + tStart * direction);
    const double f1 = field.value(origin + tEnd * direction);
    state.evaluations = 2;
    if (f0 == 0.0) {
        result.hit = true;
        result.t = tStart;
    } else {
        const double t = bisect(state, tStart, f0, tEnd, f1);
        result.hit = !std::isnan(t);
        result.t = result.hit ? t : 0.0;
    }
    result.steps = state.evaluations;
    result.evaluations = static_cast<uint64_t>(state.evaluations) * field.evaluationCost();
    return result;
}

}  // namespace isotrace::geometry
