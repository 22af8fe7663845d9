// Implicit objects whose material emits, sampled as lights. Their surfaces
// have no area measure to sample by, so a direction is drawn in the cone
// of the object's bounding sphere (uniformly over the sphere of directions
// from inside it) and traced against the object alone; the light is the
// first point of the object along it. The density is the cone's, in solid
// angle, exact for every direction that reaches the object; a path that
// hits the object by BSDF sampling meets it at that same first point, so
// MIS weighs both strategies with the same densities.
#pragma once

#include <embree3/rtcore.h>

#include "renderer/light.h"
#include "renderer/material.h"
#include "renderer/scene.h"

namespace isotrace {

class ImplicitEmitterLight final : public Light {
public:
    /// `scene` must be committed and outlive the light; `object` is an
    /// implicit object of it with an emissive material.
    ImplicitEmitterLight(const Scene& scene, const SceneObject& object, const Emission& emission);

    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override;
    double pdf(const LightSampleContext& context, const Vec3& wi, const Vec3& onLight,
               const Vec3& lightNormal) const override;
    double importance(const LightSampleContext& context) const override;
    std::optional<LightBounds> bounds() const override;
    /// By the bounding sphere: the first point along a direction must lie
    /// on the side of the plane for an image of the light to be exact.
    int sideOfPlane(const Vec3& point, const Vec3& normal) const override;

private:
    /// Density of a direction seen from p: the cone's, or the sphere's.
    double directionPdf(const Vec3& p, const Vec3& wi) const;

    RTCScene shape_;
    Mat4 worldFromObject_;
    Mat4 objectFromWorld_;
    Mat3 normalFromObject_;
    Emission emission_;
    Vec3 center_ = Vec3::Zero();  ///< bounding sphere, world space
    double radius_ = 0.0;
};

}  // namespace isotrace
