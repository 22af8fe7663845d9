// Rays against an MPU field without marching. f = N / W with W > 0, so f
// and N = sum_i w_i Q_i (plus the background's constant term inside the
// domain) share their zeros, and along a ray x(t) = o + t d every term is a
// polynomial in t: w_i = (1 - |x - c_i|^2 / R_i^2)^3 is the cube of a
// quadratic inside its ball and zero outside (with two matching
// derivatives), Q_i is a quadratic (a max or min of quadratics at sharp
// features, switching where two pieces cross). Between the t where a ball
// is entered or left or a local switches piece, N is one polynomial of
// degree 8, exactly; its first root is isolated in the Bernstein basis
// (bernstein_root.h). No Lipschitz bound, no step: a handful of polynomial
// products per local the segment meets.
#pragma once

#include <cstdint>
#include <span>

#include "geometry/pointsets/mpu_field.h"

namespace isotrace::geometry {

struct MpuSegmentRoot {
    bool hit = false;
    double t = 0.0;
    int pieces = 0;       ///< polynomial pieces searched (the work of a march's steps)
    int localTerms = 0;   ///< local functions turned into polynomials
};

/// First root of the field along origin + t direction for t in [t0, t1],
/// to within `tolerance` in t. `locals` must hold every local whose ball
/// reaches the segment, and the segment must lie in the field's domain
/// (where the background term is constant).
MpuSegmentRoot firstRootAlongSegment(const MpuField& field, MpuLocalList locals, const Vec3& origin,
                                     const Vec3& direction, double t0, double t1, double tolerance);

}  // namespace isotrace::geometry
