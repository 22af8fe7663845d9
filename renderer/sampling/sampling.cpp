#include "renderer/sampling/sampling.h"

#include <cmath>
#include <numbers>

namespace isotrace {

void orthonormalBasis(const Vec3& n, Vec3& s, Vec3& t) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    s = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    t = Vec3(b, sign + n.y() * n.y() * a, -n.y());
}

Vec3 sampleUniformSphere(const Eigen::Vector2d& u) {
    const double z = 1.0 - 2.0 * u.x();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * std::numbers::pi * u.y();
    return Vec3(r * std::cos(phi), z, r * std::sin(phi));
}

Vec3 sampleCosineHemisphere(const Vec3& n, const Eigen::Vector2d& u) {
    Vec3 t, s;
    orthonormalBasis(n, t, s);
    const double r = std::sqrt(u.x());
    const double phi = 2.0 * std::numbers::pi * u.y();
    const double z = std::sqrt(std::max(0.0, 1.0 - u.x()));
    return (r * std::cos(phi) * t + r * std::sin(phi) * s + z * n).normalized();
}

}  // namespace isotrace
