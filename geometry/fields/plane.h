// Half-space n . p <= offset (n of unit length): exact signed distance.
#pragma once

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct PlaneField {
    Vec3 normal = Vec3(0, 1, 0);
    double offset = 0.0;

    double value(const Vec3& p) const { return normal.dot(p) - offset; }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        gradient = normal;
        return value(p);
    }
    Interval range(const Box3& box) const {
        const double c = value(box.center());
        const double spread = normal.cwiseAbs().dot(0.5 * box.extent());
        return {c - spread, c + spread};
    }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const { return Box3::everything(); }
};

}  // namespace isotrace::geometry
