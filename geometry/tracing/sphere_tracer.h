// Ray-surface intersection of a field along one ray segment.
//
// sphereTrace steps by |f| / L, which can never cross the surface when L
// bounds the gradient over the region marched, brackets the first sign change
// and refines it by safeguarded secant/bisection. interval bisection is the
// slow, robust reference (and the fallback when a march runs out of steps).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "geometry/field_program.h"

namespace isotrace::geometry {

struct TraceResult {
    bool hit = false;
    double t = 0.0;
    int steps = 0;             ///< field evaluations made while marching
    uint64_t evaluations = 0;  ///< node evaluations (steps times program cost)
    /// The field's gradient at the hit, when the tracer already has it
    /// (saves the caller an evaluation).
    bool gradientKnown = false;
    Vec3 gradient = Vec3::Zero();
};

struct TraceSettings {
    /// Distance resolution: marching never takes a step shorter than this,
    /// and roots are refined to well below it.
    double epsilon = 1e-6;
    int maxSteps = 2000;
    /// Steps go up to this multiple of the proven safe distance while each
    /// is justified after the fact (1: plain sphere tracing).
    double overRelaxation = 1.6;
    /// An occlusion query: any root proven in the segment will do, at any t
    /// within it, with an approximate gradient. Tracers that can prove a
    /// sign change from their models then need no exact evaluation; the
    /// others answer as for a nearest hit.
    bool anyHit = false;
};

/// Marches origin + t * direction for t in [tStart, tEnd]. `lipschitz` must
/// bound |grad f| over every point of that segment.
TraceResult sphereTrace(const FieldProgram& field, double lipschitz, const Vec3& origin, const Vec3& direction,
                        double tStart, double tEnd, const TraceSettings& settings);

/// Reference intersector: bisects the segment, discarding pieces whose value
/// range (interval and Lipschitz enclosures) excludes zero, and returns the
/// first sign change found at resolution epsilon.
TraceResult intervalBisectionTrace(const FieldProgram& field, const Vec3& origin, const Vec3& direction,
                                   double tStart, double tEnd, const TraceSettings& settings);

/// Refines a bracket [ta, tb] whose ends have values of opposite sign.
double refineRoot(const FieldProgram& field, const Vec3& origin, const Vec3& direction, double ta, double fa,
                  double tb, double fb, double tolerance, int* evaluations);

/// Entry and exit parameters of a ray in a box (empty when tEnter > tExit).
bool clipRayToBox(const Box3& box, const Vec3& origin, const Vec3& direction, double& tEnter, double& tExit);

/// Where a ray is within a slab around a plane: the span [enter, leave] of t
/// with |alpha + beta t| <= band (the plane's value along the ray); the whole
/// line when beta is 0 and |alpha| <= band; false when never.
inline bool raySlabSpan(double alpha, double beta, double band, double& enter, double& leave) {
    if (beta == 0) {
        enter = -std::numeric_limits<double>::infinity();
        leave = std::numeric_limits<double>::infinity();
        return std::abs(alpha) <= band;
    }
    enter = (-std::copysign(band, beta) - alpha) / beta;
    leave = (std::copysign(band, beta) - alpha) / beta;
    return true;
}

}  // namespace isotrace::geometry
