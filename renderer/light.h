// Light sources. Point and directional lights are delta lights; area lights
// (quads, disks and emissive meshes) are world-space triangles sampled by
// area; the environment is a constant radiance from every direction.
#pragma once

#include <array>
#include <Eigen/Core>
#include <vector>

#include "color.h"
#include "ray.h"

namespace isotrace {

struct LightSample {
    RGB radiance = RGB::Zero();  ///< incident radiance (or intensity / d^2 for delta lights)
    Vec3 direction;              ///< unit, from the shading point towards the light
    double distance = 0.0;       ///< to the sampled point; infinity for directional and environment
    double pdf = 0.0;            ///< solid-angle density (1 for delta lights)
    bool isDelta = false;
};

class Light {
public:
    enum class Type { Point, Directional, Area, Environment };

    static Light point(const Vec3& position, const RGB& intensity);
    /// `direction` is the direction light travels; `irradiance` falls on a
    /// surface facing it.
    static Light directional(const Vec3& direction, const RGB& irradiance);
    static Light area(std::vector<std::array<Vec3, 3>> triangles, const RGB& radiance, bool twoSided);
    static Light environment(const RGB& radiance);

    Type type() const { return type_; }
    bool isDelta() const { return type_ == Type::Point || type_ == Type::Directional; }
    const RGB& radiance() const { return radiance_; }
    bool twoSided() const { return twoSided_; }
    double area() const { return totalArea_; }
    const std::vector<std::array<Vec3, 3>>& triangles() const { return triangles_; }

    LightSample sample(const Vec3& p, const Eigen::Vector2d& u) const;
    /// Solid-angle density with which sample() picks the point `onLight`
    /// (normal `lightNormal`) seen from `p`; environment: any direction.
    double pdf(const Vec3& p, const Vec3& onLight, const Vec3& lightNormal) const;
    /// Radiance leaving an area light's point with normal n towards direction w.
    RGB emitted(const Vec3& n, const Vec3& w) const;

private:
    Type type_ = Type::Point;
    Vec3 position_ = Vec3::Zero();
    Vec3 direction_ = Vec3(0, -1, 0);
    RGB radiance_ = RGB::Zero();  ///< intensity (point), irradiance (directional), radiance (area, environment)
    bool twoSided_ = false;
    std::vector<std::array<Vec3, 3>> triangles_;
    std::vector<double> cumulativeArea_;
    double totalArea_ = 0.0;
};

}  // namespace isotrace
