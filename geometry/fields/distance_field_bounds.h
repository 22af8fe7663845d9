// Ranges shared by fields whose gradient length is at most L everywhere.
#pragma once

#include "geometry/bounding_box.h"

namespace isotrace::geometry {

/// Values of an L-Lipschitz field over `box`, from its value at the centre:
/// every point lies within half the diagonal of the centre.
inline Interval rangeFromLipschitz(double valueAtCenter, double lipschitz, const Box3& box) {
    const double spread = lipschitz * box.halfDiagonal();
    return {valueAtCenter - spread, valueAtCenter + spread};
}

/// Unit vector along v, or a fixed unit vector where v vanishes (the
/// gradient of a distance is undefined there; any unit vector bounds it).
inline Vec3 safeNormalized(const Vec3& v) {
    const double n = v.norm();
    return n > 0 ? Vec3(v / n) : Vec3(0, 1, 0);
}

}  // namespace isotrace::geometry
