// Lights seen in plane mirrors, sampled as their mirror images (the image
// sources of acoustics). Light that leaves a lamp, reflects once off a flat
// mirror and lands on a diffuse surface is a caustic: a path tracer finds it
// only when a BSDF sample happens to bounce off the mirror into the lamp,
// and never for a point light. Seen from a point p, the lamp in the mirror
// is the lamp seen from p's reflection p' through the plane: sampling the
// lamp from p' and reflecting the direction back gives a direction at p,
// its solid-angle density (the unfolded path's) and the radiance. The
// shadow ray then has two legs, p to the mirror and the mirror to the lamp
// (shadowRayWeight in integrator.h), and carries the mirror's reflectance.
// The path integrator weighs these samples by MIS against BSDF samples
// that reach the lamp by one bounce off the same mirror.
#pragma once

#include <vector>

#include "renderer/light.h"
#include "renderer/object_lights.h"
#include "renderer/plane_mirror.h"

namespace isotrace {

class MirrorImageLight final : public Light {
public:
    /// `light` seen in `mirror` (index `mirrorIndex` of Scene::planeMirrors);
    /// the light lies wholly on side `side` (+1 or -1 along the normal).
    MirrorImageLight(const Light& light, const MirrorPlane& plane, int mirrorIndex, int side);

    bool isDelta() const override { return light_.isDelta(); }
    bool isInfinite() const override { return light_.isInfinite(); }
    /// Samples carry `mirror`; `point` is the image of the point on the
    /// light.
    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override;
    /// `onLight` is the real point on the light, `wi` the direction at the
    /// context towards the mirror.
    double pdf(const LightSampleContext& context, const Vec3& wi, const Vec3& onLight,
               const Vec3& lightNormal) const override;
    /// The light's importance seen from the reflected point (the mirror's
    /// reflectance taken as one, its extent as unbounded).
    double importance(const LightSampleContext& context) const override;
    /// The light's bounds reflected in the plane.
    std::optional<LightBounds> bounds() const override;
    int sideOfPlane(const Vec3& point, const Vec3& normal) const override { return 0; }

private:
    /// Height of p above the plane on the light's side (positive where the
    /// image can light it).
    double height(const Vec3& p) const { return side_ * plane_.signedDistance(p); }
    LightSampleContext reflected(const LightSampleContext& c) const {
        return {plane_.reflectPoint(c.p), plane_.reflectVector(c.n)};
    }

    const Light& light_;
    MirrorPlane plane_;
    int mirrorIndex_;
    double side_;
};

}  // namespace isotrace
