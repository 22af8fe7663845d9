// Box with optionally rounded edges: exact signed distance.
#pragma once

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct BoxField {
    Vec3 center = Vec3::Zero();
    Vec3 halfSize = Vec3::Ones();
    double rounding = 0.0;  ///< edge radius, at most the smallest half size

    double value(const Vec3& p) const {
        Vec3 g;
        return valueAndGradient(p, g);
    }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 d = p - center;
        const Vec3 q = d.cwiseAbs() - (halfSize - Vec3::Constant(rounding));
        const Vec3 outside = q.cwiseMax(0.0);
        const double outsideLength = outside.norm();
        Vec3 sign(d.x() < 0 ? -1.0 : 1.0, d.y() < 0 ? -1.0 : 1.0, d.z() < 0 ? -1.0 : 1.0);
        if (outsideLength > 0) {
            gradient = sign.cwiseProduct(outside / outsideLength);
            return outsideLength - rounding;
        }
        int axis;
        const double inside = q.maxCoeff(&axis);
        gradient = Vec3::Zero();
        gradient[axis] = sign[axis];
        return inside - rounding;
    }
    Interval range(const Box3& box) const { return rangeFromLipschitz(value(box.center()), 1.0, box); }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const { return {center - halfSize, center + halfSize}; }
};

}  // namespace isotrace::geometry
