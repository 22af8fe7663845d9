#include "renderer/sampling.h"

#include <cmath>
#include <numbers>

namespace isotrace {

Vec3 sampleCosineHemisphere(const Vec3& n, const Eigen::Vector2d& u) {
    // Orthonormal basis without branches on the normal's direction (Duff et al. 2017).
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    const Vec3 t(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    const Vec3 s(b, sign + n.y() * n.y() * a, -n.y());
    const double r = std::sqrt(u.x());
    const double phi = 2.0 * std::numbers::pi * u.y();
    const double z = std::sqrt(std::max(0.0, 1.0 - u.x()));
    return (r * std::cos(phi) * t + r * std::sin(phi) * s + z * n).normalized();
}

}  // namespace isotrace
