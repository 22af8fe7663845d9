// Sphere tracing a variational field through its local models: each step
// costs a degree-4 polynomial and a few near terms instead of a sum over
// every constraint, and never crosses the exact surface.
//
// Far from the surface a model's value error e bounds |f - model|, so
// (|model| - e) / L is a safe step. Where |model| <= e the model cannot tell
// the sign; there the exact field is evaluated once (an "anchor"), and
// because the gradient of f - model is at most g (the gradient error) the
// model shifted by the anchor's exact difference is within g times the
// distance from the anchor, and with the anchor's exact gradient the
// drift shrinks to the Hessian error times the distance squared: the steps
// go on, cheaply, to within the distance resolution of the surface, where
// the model proves the sign change within one forced step and a Newton
// step from the anchor (with the exact gradient it brought) gives the hit.
//
// Each step is the longer of two proven ones: margin / L, and the reach of
// the parabola below |f| built from the model's value and slope at the
// point, the model's curvature bound and the error's bound (the value error,
// or the drift from the anchor): near the surface a Newton-like step
// instead of a geometric crawl (on the hand 4x fewer steps).
//
// Before the first anchor, a closest-hit query tries the model alone: near
// the model's centre its error falls as the fifth power of the distance
// (VariationalPatch::valueErrorWithin), and where that error is below the
// model's margins the model itself proves the sign up to half a minStep
// before its root and the other sign half a minStep after it. The hit is
// then the model's root, with the model's gradient, and costs no exact sum
// (on the hand, most hits).
#pragma once

#include "geometry/variational/variational_patch.h"

namespace isotrace::geometry {

struct PatchTraceResult {
    /// False when the march ran out of steps (a ray grazing the surface for
    /// a long way): the caller settles [t, tEnd] another way.
    bool complete = true;
    bool hit = false;
    double t = 0.0;
    /// Exact, at the last anchor (within resolution of the hit); for an
    /// any-hit query the model's where the model proved the hit.
    Vec3 gradient = Vec3::Zero();
    int steps = 0;                 ///< model evaluations
    int exactEvaluations = 0;      ///< evaluations of the exact field
    /// The hit was proven by the model alone, near its expansion point
    /// where its error is small (within minStep / 2 of f's root).
    bool modelHit = false;
};

/// First root of `field` along origin + t direction for t in [tStart, tEnd],
/// a segment inside the model's box. Marching never skips a piece of
/// surface thicker than minStep (in t) along the ray, and brackets the hit
/// to one step of minStep before the Newton step; a hit the model proves
/// alone (modelHit) is within minStep / 2 of f's first root.
///
/// With anyHit (an occlusion query), a sign change the model proves is
/// enough: the sign known where the ray was last cleared and the opposite
/// sign the model proves a little past its own root mean a root lies
/// between (f is continuous), so most hits need no exact evaluation; t is
/// then that second point.
PatchTraceResult tracePatch(const VariationalPatch& patch, const VariationalField& field, const Vec3& origin,
                            const Vec3& direction, double tStart, double tEnd, double minStep, bool anyHit = false,
                            int maxSteps = 4000);

}  // namespace isotrace::geometry
