#include "renderer/lights/area_light.h"

#include <algorithm>
#include <cmath>

#include "geometry/bounding_box.h"
#include "renderer/object_lights.h"

namespace isotrace {

AreaLight::AreaLight(std::vector<std::array<Vec3, 3>> triangles, const Emission& emission)
    : emission_(emission), triangles_(std::move(triangles)) {
    geometry::Box3 box;
    for (const auto& t : triangles_) {
        totalArea_ += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
        cumulativeArea_.push_back(totalArea_);
        for (const Vec3& v : t) box.extend(v);
    }
    if (triangles_.empty()) return;
    center_ = box.center();
    for (const auto& t : triangles_)
        for (const Vec3& v : t) radius_ = std::max(radius_, (v - center_).norm());
    if (emission_.twoSided) return;
    // One normal for all (a quad, a disk, a flat mesh): points behind it get no light.
    const Vec3 first = (triangles_[0][1] - triangles_[0][0]).cross(triangles_[0][2] - triangles_[0][0]).normalized();
    for (const auto& t : triangles_) {
        const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
        if (n.norm() > 0 && n.normalized().dot(first) < 1.0 - 1e-9) return;
    }
    normal_ = first;
}

double AreaLight::importance(const LightSampleContext& context) const {
    if (triangles_.empty()) return 0.0;
    const Vec3 toLight = center_ - context.p;
    const double d = toLight.norm();
    const double slack = sphereSinHalfAngle(radius_, d);
    const Vec3 w = d > 0 ? Vec3(toLight / d) : Vec3(0, 0, 1);
    const double cosLight = normal_.isZero() ? 1.0 : cosineBound(normal_, -w, slack);
    const double cosReceiver = context.n.isZero() ? 1.0 : cosineBound(context.n, w, slack);
    if (!(cosLight > 0) || !(cosReceiver > 0)) return 0.0;
    // Irradiance of a small emitter L A cos cos / d^2, not above its value
    // at the bounding sphere's surface.
    return luminance(emission_.radiance) * totalArea_ * cosLight * cosReceiver / std::max(d * d, radius_ * radius_);
}

std::optional<LightBounds> AreaLight::bounds() const {
    if (triangles_.empty()) return std::nullopt;
    LightBounds b;
    for (const auto& t : triangles_)
        for (const Vec3& v : t) b.box.extend(v);
    b.power = luminance(emission_.radiance) * totalArea_;
    // A flat one-sided emitter faces one way; any other, every way.
    if (!normal_.isZero()) b.axis = normal_, b.cosNormalSpread = 1.0;
    else b.cosNormalSpread = -1.0, b.twoSided = emission_.twoSided;
    b.cosEmissionSpread = 0.0;
    return b;
}

int AreaLight::sideOfPlane(const Vec3& point, const Vec3& normal) const {
    int side = 0;
    for (const auto& t : triangles_)
        for (const Vec3& v : t) {
            const double h = normal.dot(v - point);
            const int s = h > 0 ? 1 : h < 0 ? -1 : 0;
            if (s == 0 || (side != 0 && s != side)) return 0;
            side = s;
        }
    return side;
}

LightSample AreaLight::sample(const LightSampleContext& context, const Eigen::Vector2d& u) const {
    const Vec3& p = context.p;
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
    s.point = q;
    s.distance = d.norm();
    if (!(s.distance > 0)) return s;
    s.direction = d / s.distance;
    s.radiance = emission_.emitted(n, -s.direction);
    s.pdf = pdf(context, s.direction, q, n);
    return s;
}

double AreaLight::pdf(const LightSampleContext& context, const Vec3&, const Vec3& onLight, const Vec3& lightNormal) const {
    const Vec3 d = onLight - context.p;
    const double dist2 = d.squaredNorm();
    const double cosLight = std::abs(lightNormal.dot(d)) / std::sqrt(dist2);
    if (!(cosLight > 0)) return 0.0;
    return dist2 / (cosLight * totalArea_);
}

std::unique_ptr<Light> makeAreaLight(std::vector<std::array<Vec3, 3>> triangles, const Emission& emission) {
    return std::make_unique<AreaLight>(std::move(triangles), emission);
}

}  // namespace isotrace
