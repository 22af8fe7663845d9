// Ellipsoid: min(r) * (|(p - c) / r| - 1). Not the exact distance, but a
// 1-Lipschitz function that vanishes on the ellipsoid, so |f| never exceeds
// the distance to the surface and sphere tracing stays safe.
#pragma once

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct EllipsoidField {
    Vec3 center = Vec3::Zero();
    Vec3 radii = Vec3::Ones();

    double value(const Vec3& p) const { return radii.minCoeff() * (((p - center).cwiseQuotient(radii)).norm() - 1.0); }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 q = (p - center).cwiseQuotient(radii);
        const double k = q.norm();
        const double scale = radii.minCoeff();
        gradient = k > 0 ? Vec3(scale * q.cwiseQuotient(radii) / k) : Vec3(0, 1, 0);
        return scale * (k - 1.0);
    }
    Interval range(const Box3& box) const { return rangeFromLipschitz(value(box.center()), 1.0, box); }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const { return {center - radii, center + radii}; }
};

}  // namespace isotrace::geometry
