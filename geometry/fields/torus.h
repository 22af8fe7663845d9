// Torus around the y axis: exact signed distance to a circle of radius
// `major` in the xz plane, minus `minor`.
#pragma once

#include <cmath>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

// sqrt(a^2 + b^2) without std::hypot's guards against overflow, which cost
// a tenth of a render of the comparison scene; scene coordinates are far
// from 1e150.
inline double planarLength(double a, double b) { return std::sqrt(a * a + b * b); }

struct TorusField {
    Vec3 center = Vec3::Zero();
    double major = 1.0;
    double minor = 0.25;

    double value(const Vec3& p) const {
        const Vec3 d = p - center;
        const double radial = planarLength(d.x(), d.z()) - major;
        return planarLength(radial, d.y()) - minor;
    }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 d = p - center;
        const double rho = planarLength(d.x(), d.z());
        const double radial = rho - major;
        const double len = planarLength(radial, d.y());
        // Direction from the nearest point of the core circle to p.
        const double gr = len > 0 ? radial / len : 1.0;
        const double gy = len > 0 ? d.y() / len : 0.0;
        const double cx = rho > 0 ? d.x() / rho : 1.0, cz = rho > 0 ? d.z() / rho : 0.0;
        gradient = Vec3(gr * cx, gy, gr * cz);
        return len - minor;
    }
    Interval range(const Box3& box) const { return rangeFromLipschitz(value(box.center()), 1.0, box); }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const {
        const double r = major + minor;
        return {center - Vec3(r, minor, r), center + Vec3(r, minor, r)};
    }
};

}  // namespace isotrace::geometry
