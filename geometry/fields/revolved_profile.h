// Solids of revolution about the y axis (capped cylinder, capped cone):
// exact signed distance to a convex profile polygon in the (radius, y)
// half-plane. The distance in 3D equals the distance in the meridian plane.
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct RevolvedProfileField {
    using Vec2 = Eigen::Vector2d;
    Vec3 center = Vec3::Zero();
    /// Counter-clockwise in (radius, y); edges lying on the axis are interior.
    std::array<Vec2, 4> profile{};

    static RevolvedProfileField cylinder(const Vec3& center, double radius, double height) {
        return cone(center, radius, radius, height);
    }
    /// Bottom (y = -height/2) radius r0, top radius r1.
    static RevolvedProfileField cone(const Vec3& center, double r0, double r1, double height) {
        const double h = 0.5 * height;
        return {center, {Vec2(0, -h), Vec2(r0, -h), Vec2(r1, h), Vec2(0, h)}};
    }

    double value(const Vec3& p) const {
        Vec3 g;
        return valueAndGradient(p, g);
    }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const {
        const Vec3 d = p - center;
        const double rho = std::sqrt(d.x() * d.x() + d.z() * d.z());
        const Vec2 q(rho, d.y());
        double best = std::numeric_limits<double>::infinity();
        // The signed distance's gradient: beside an edge its outward normal,
        // whichever side q is on; near a vertex the direction from it.
        // Taking the normal directly matters on the surface, where the
        // offset to the edge is rounding noise of either sign and sphere
        // tracing leaves its hits.
        Vec2 bestGradient(1, 0);
        bool nearestIsVertex = false;
        bool inside = true;
        for (int i = 0; i < 4; ++i) {
            const Vec2& a = profile[i];
            const Vec2& b = profile[(i + 1) % 4];
            const Vec2 e = b - a;
            const Vec2 w = q - a;
            if (e.x() * w.y() - e.y() * w.x() < 0) inside = false;
            if (a.x() == 0 && b.x() == 0) continue;  // on the axis: not a boundary
            const double len2 = e.squaredNorm();
            const double t = len2 > 0 ? std::clamp(w.dot(e) / len2, 0.0, 1.0) : 0.0;
            const Vec2 offset = w - t * e;
            const double dist = offset.norm();
            if (dist < best) {
                best = dist;
                const Vec2 normal = Vec2(e.y(), -e.x()).normalized();
                nearestIsVertex = (t <= 0 || t >= 1) && dist > 0;
                bestGradient = nearestIsVertex ? Vec2(offset / dist) : normal;
            }
        }
        const double sign = inside ? -1.0 : 1.0;
        if (nearestIsVertex) bestGradient *= sign;
        const double cx = rho > 0 ? d.x() / rho : 1.0, cz = rho > 0 ? d.z() / rho : 0.0;
        gradient = Vec3(bestGradient.x() * cx, bestGradient.y(), bestGradient.x() * cz);
        return sign * best;
    }
    Interval range(const Box3& box) const { return rangeFromLipschitz(value(box.center()), 1.0, box); }
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const {
        double r = 0, y0 = profile[0].y(), y1 = profile[0].y();
        for (const Vec2& v : profile) {
            r = std::max(r, v.x());
            y0 = std::min(y0, v.y());
            y1 = std::max(y1, v.y());
        }
        return {center + Vec3(-r, y0, -r), center + Vec3(r, y1, r)};
    }
};

}  // namespace isotrace::geometry
