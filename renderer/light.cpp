#include "light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace isotrace {

Light Light::point(const Vec3& position, const RGB& intensity) {
    Light l;
    l.type_ = Type::Point;
    l.position_ = position;
    l.radiance_ = intensity;
    return l;
}

Light Light::directional(const Vec3& direction, const RGB& irradiance) {
    Light l;
    l.type_ = Type::Directional;
    l.direction_ = direction.normalized();
    l.radiance_ = irradiance;
    return l;
}

Light Light::area(std::vector<std::array<Vec3, 3>> triangles, const RGB& radiance, bool twoSided) {
    Light l;
    l.type_ = Type::Area;
    l.radiance_ = radiance;
    l.twoSided_ = twoSided;
    l.triangles_ = std::move(triangles);
    for (const auto& t : l.triangles_) {
        l.totalArea_ += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
        l.cumulativeArea_.push_back(l.totalArea_);
    }
    return l;
}

Light Light::environment(const RGB& radiance) {
    Light l;
    l.type_ = Type::Environment;
    l.radiance_ = radiance;
    return l;
}

RGB Light::emitted(const Vec3& n, const Vec3& w) const {
    if (type_ != Type::Area) return RGB::Zero();
    return (twoSided_ || n.dot(w) > 0) ? radiance_ : RGB::Zero();
}

LightSample Light::sample(const Vec3& p, const Eigen::Vector2d& u) const {
    LightSample s;
    constexpr double inf = std::numeric_limits<double>::infinity();
    switch (type_) {
        case Type::Point: {
            const Vec3 d = position_ - p;
            s.distance = d.norm();
            s.direction = d / s.distance;
            s.radiance = radiance_ / (s.distance * s.distance);
            s.pdf = 1.0;
            s.isDelta = true;
            return s;
        }
        case Type::Directional:
            s.direction = -direction_;
            s.distance = inf;
            s.radiance = radiance_;
            s.pdf = 1.0;
            s.isDelta = true;
            return s;
        case Type::Environment: {
            // Uniform over the sphere.
            const double z = 1.0 - 2.0 * u.x();
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double phi = 2.0 * std::numbers::pi * u.y();
            s.direction = Vec3(r * std::cos(phi), z, r * std::sin(phi));
            s.distance = inf;
            s.radiance = radiance_;
            s.pdf = 1.0 / (4.0 * std::numbers::pi);
            return s;
        }
        case Type::Area: {
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
            s.radiance = emitted(n, -s.direction);
            s.pdf = pdf(p, q, n);
            return s;
        }
    }
    return s;
}

double Light::pdf(const Vec3& p, const Vec3& onLight, const Vec3& lightNormal) const {
    if (type_ == Type::Environment) return 1.0 / (4.0 * std::numbers::pi);
    if (type_ != Type::Area) return 0.0;
    const Vec3 d = onLight - p;
    const double dist2 = d.squaredNorm();
    const double cosLight = std::abs(lightNormal.dot(d)) / std::sqrt(dist2);
    if (!(cosLight > 0)) return 0.0;
    return dist2 / (cosLight * totalArea_);
}

}  // namespace isotrace
