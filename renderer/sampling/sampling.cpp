#include "renderer/sampling/sampling.h"

#include <algorithm>
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

double sampleLinear(double u, double a, double b) {
    if (u == 0.0 || a == b) return u;
    // The root of ((1 - x) a + x b)-weighted CDF = u that stays accurate
    // when a or b is zero: x = u (a + b) / (a + sqrt(lerp(u, a^2, b^2))).
    const double x = u * (a + b) / (a + std::sqrt((1.0 - u) * a * a + u * b * b));
    return std::min(x, 0x1.fffffffffffffp-1);
}

Eigen::Vector2d sampleBilinear(const Eigen::Vector2d& u, double a00, double a10, double a01, double a11) {
    const double y = sampleLinear(u[1], a00 + a10, a01 + a11);
    const double x = sampleLinear(u[0], (1.0 - y) * a00 + y * a01, (1.0 - y) * a10 + y * a11);
    return {x, y};
}

double bilinearPdf(const Eigen::Vector2d& p, double a00, double a10, double a01, double a11) {
    const double sum = a00 + a10 + a01 + a11;
    if (!(sum > 0)) return 1.0;
    const double x = p[0], y = p[1];
    return 4.0 * ((1 - x) * (1 - y) * a00 + x * (1 - y) * a10 + (1 - x) * y * a01 + x * y * a11) / sum;
}

}  // namespace isotrace
