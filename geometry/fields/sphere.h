// Sphere: exact signed distance |p - c| - r.
#pragma once

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct SphereField {
    Vec3 center = Vec3::Zero();
    double radius = 1.0;

    double value(const Vec3& p) const { return (p - center).norm() - radius; }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 d = p - center;
        gradient = safeNormalized(d);
        return d.norm() - radius;
    }
    Interval range(const Box3& box) const {
        const Interval d = box.distanceRange(center);
        return {d.lo - radius, d.hi - radius};
    }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const { return Box3::around(center, radius); }
};

}  // namespace isotrace::geometry
