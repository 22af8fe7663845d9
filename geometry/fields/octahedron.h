// Regular octahedron: the points with |x| + |y| + |z| <= size about its
// centre (vertices `size` from the centre along the axes). The value is
// (|x| + |y| + |z| - size) / sqrt(3), the distance to the plane of the
// nearest face: exact inside and above the faces, never larger than the
// distance near edges and vertices, so it is 1-Lipschitz and sphere tracing
// stays safe.
#pragma once

#include <cmath>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct OctahedronField {
    Vec3 center = Vec3::Zero();
    double size = 1.0;

    static constexpr double kInverseSqrt3 = 0.57735026918962576;

    double value(const Vec3& p) const { return ((p - center).cwiseAbs().sum() - size) * kInverseSqrt3; }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 d = p - center;
        // The face's normal; on a plane of symmetry either side's will do.
        gradient = Vec3(d.x() < 0 ? -1 : 1, d.y() < 0 ? -1 : 1, d.z() < 0 ? -1 : 1) * kInverseSqrt3;
        return (d.cwiseAbs().sum() - size) * kInverseSqrt3;
    }
    Interval range(const Box3& box) const { return rangeFromLipschitz(value(box.center()), 1.0, box); }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const { return Box3::around(center, size); }
};

}  // namespace isotrace::geometry
