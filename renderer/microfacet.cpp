#include "renderer/microfacet.h"

#include <algorithm>
#include <numbers>

namespace isotrace {

double TrowbridgeReitz::D(const Vec3& m) const {
    if (!(m.z() > 0)) return 0.0;  // facets face up
    const double cos2 = m.z() * m.z();
    // 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2): no tangents or angles needed.
    const double x = m.x() / alphaX_, y = m.y() / alphaY_;
    const double s = x * x + y * y + cos2;
    return 1.0 / (std::numbers::pi * alphaX_ * alphaY_ * s * s);
}

double TrowbridgeReitz::lambda(const Vec3& w) const {
    const double cos2 = w.z() * w.z();
    if (!(cos2 > 0)) return INFINITY;
    const double ax = w.x() * alphaX_, ay = w.y() * alphaY_;
    const double alpha2Tan2 = (ax * ax + ay * ay) / cos2;
    return 0.5 * (std::sqrt(1.0 + alpha2Tan2) - 1.0);
}

double TrowbridgeReitz::visibleD(const Vec3& w, const Vec3& m) const {
    const double cosW = std::abs(w.z());
    if (!(cosW > 0)) return 0.0;
    return G1(w) / cosW * D(m) * std::max(0.0, w.dot(m));
}

Vec3 TrowbridgeReitz::sampleVisibleNormal(const Vec3& w, const Eigen::Vector2d& u) const {
    // Stretch to the configuration where the distribution is a hemisphere of
    // unit radius, sample the projected hemisphere seen from w there, unstretch.
    Vec3 wh = Vec3(alphaX_ * w.x(), alphaY_ * w.y(), w.z()).normalized();
    if (wh.z() < 0) wh = -wh;
    const Vec3 t1 = wh.z() < 0.99999 ? Vec3(Vec3(0, 0, 1).cross(wh).normalized()) : Vec3(1, 0, 0);
    const Vec3 t2 = wh.cross(t1);
    const double r = std::sqrt(u[0]), phi = 2.0 * std::numbers::pi * u[1];
    double px = r * std::cos(phi), py = r * std::sin(phi);
    const double h = std::sqrt(1.0 - px * px);
    const double s = 0.5 * (1.0 + wh.z());
    py = (1.0 - s) * h + s * py;
    const double pz = std::sqrt(std::max(0.0, 1.0 - px * px - py * py));
    const Vec3 nh = px * t1 + py * t2 + pz * wh;
    return Vec3(alphaX_ * nh.x(), alphaY_ * nh.y(), std::max(1e-6, nh.z())).normalized();
}

}  // namespace isotrace
