#include "renderer/area_light.h"

#include <algorithm>
#include <cmath>

namespace isotrace {

AreaLight::AreaLight(std::vector<std::array<Vec3, 3>> triangles, const Emission& emission)
    : emission_(emission), triangles_(std::move(triangles)) {
    for (const auto& t : triangles_) {
        totalArea_ += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
        cumulativeArea_.push_back(totalArea_);
    }
}

LightSample AreaLight::sample(const Vec3& p, const Eigen::Vector2d& u) const {
    LightSample s;
    // Pick a triangle by area, reusing u.x for the point inside it.
    const double target = u.x() * totalArea_;
    const size_t i = std::min<size_t>(
        std::upper_bound(cumulativeArea_.begin(), cumulativeArea_.end(), target) - cumulativeArea_.begin(),
        triangles_.size() - 1);
    const double before = i == 0 ? 0.0 : cumulativeArea_[i - 1];
    const double width = cumulativeArea_[i] - before;
    const double u0 = width > 0 ? std::clamp((target - before) / width, 0.0, 1.0) : 0.5;
    const double su = std::sqrt(u0);
    const double b0 = 1.0 - su, b1 = u.y() * su;
    const auto& t = triangles_[i];
    const Vec3 q = b0 * t[0] + b1 * t[1] + (1.0 - b0 - b1) * t[2];
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    const Vec3 d = q - p;
    s.distance = d.norm();
    if (!(s.distance > 0)) return s;
    s.direction = d / s.distance;
    s.radiance = emission_.emitted(n, -s.direction);
    s.pdf = pdf(p, q, n);
    return s;
}

double AreaLight::pdf(const Vec3& p, const Vec3& onLight, const Vec3& lightNormal) const {
    const Vec3 d = onLight - p;
    const double dist2 = d.squaredNorm();
    const double cosLight = std::abs(lightNormal.dot(d)) / std::sqrt(dist2);
    if (!(cosLight > 0)) return 0.0;
    return dist2 / (cosLight * totalArea_);
}

}  // namespace isotrace
