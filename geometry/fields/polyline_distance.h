// Distance surfaces around a point, a segment (capsule) or a polyline:
// exact signed distance to the skeleton minus a radius.
#pragma once

#include <limits>
#include <vector>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct PolylineDistanceField {
    std::vector<Vec3> points;  ///< one point, or the vertices of a polyline
    double radius = 0.5;

    /// Nearest point of the skeleton to p.
    Vec3 nearestOnSkeleton(const Vec3& p) const {
        if (points.size() == 1) return points[0];
        Vec3 best = points[0];
        double bestDist2 = std::numeric_limits<double>::infinity();
        for (size_t i = 0; i + 1 < points.size(); ++i) {
            const Vec3 e = points[i + 1] - points[i];
            const double len2 = e.squaredNorm();
            const double t = len2 > 0 ? std::clamp((p - points[i]).dot(e) / len2, 0.0, 1.0) : 0.0;
            const Vec3 q = points[i] + t * e;
            const double d2 = (p - q).squaredNorm();
            if (d2 < bestDist2) {
                bestDist2 = d2;
                best = q;
            }
        }
        return best;
    }
    double value(const Vec3& p) const { return (p - nearestOnSkeleton(p)).norm() - radius; }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 d = p - nearestOnSkeleton(p);
        gradient = safeNormalized(d);
        return d.norm() - radius;
    }
    Interval range(const Box3& box) const { return rangeFromLipschitz(value(box.center()), 1.0, box); }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const {
        Box3 b;
        for (const Vec3& p : points) b.extend(p);
        return b.expanded(radius);
    }
};

}  // namespace isotrace::geometry
