// Area lights: world-space emissive triangles, sampled by area (a triangle
// in proportion to its area, then a uniform point in it). Quad and disk
// lights and every emissive mesh become one.
#pragma once

#include <array>
#include <vector>

#include "renderer/light.h"
#include "renderer/material.h"

namespace isotrace {

class AreaLight final : public Light {
public:
    AreaLight(std::vector<std::array<Vec3, 3>> triangles, const Emission& emission);

    double area() const { return totalArea_; }
    const std::vector<std::array<Vec3, 3>>& triangles() const { return triangles_; }

    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override;
    double pdf(const LightSampleContext& context, const Vec3& wi, const Vec3& onLight,
               const Vec3& lightNormal) const override;
    double importance(const LightSampleContext& context) const override;
    std::optional<LightBounds> bounds() const override;
    int sideOfPlane(const Vec3& point, const Vec3& normal) const override;

private:
    Emission emission_;
    std::vector<std::array<Vec3, 3>> triangles_;
    std::vector<double> cumulativeArea_;
    double totalArea_ = 0.0;
    // Bounds for importance(): a sphere around the triangles, and the one
    // normal of a flat one-sided emitter (zero otherwise).
    Vec3 center_ = Vec3::Zero();
    double radius_ = 0.0;
    Vec3 normal_ = Vec3::Zero();
};

}  // namespace isotrace
