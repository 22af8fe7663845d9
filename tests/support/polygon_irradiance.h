// Irradiance from a Lambertian polygon, the closed form area-light tests
// compare against.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/vector_types.h"

namespace isotrace::testing {

/// Irradiance at x (surface normal n) from a Lambertian polygon of radiance
/// L (Lambert 1760): E = L/2 |sum_i angle(v_i, v_i+1) n . unit(v_i x v_i+1)|,
/// v_i the vertices relative to x.
inline double polygonIrradiance(const geometry::Vec3& x, const geometry::Vec3& n,
                                const std::vector<geometry::Vec3>& polygon, double radiance) {
    double sum = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const geometry::Vec3 a = (polygon[i] - x).normalized(), b = (polygon[(i + 1) % polygon.size()] - x).normalized();
        const geometry::Vec3 c = a.cross(b);
        sum += std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * n.dot(c.normalized());
    }
    return 0.5 * radiance * std::abs(sum);
}

}  // namespace isotrace::testing
