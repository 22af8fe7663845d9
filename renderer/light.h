// Light sources. Point, spot and directional lights are delta lights; area lights
// are emissive triangles sampled by area (quads, disks and emissive meshes);
// the environment surrounds the scene. Each type is one file in lights/,
// listed in lights/light_types.cpp.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

#include "renderer/color.h"
#include "renderer/light_bounds.h"
#include "renderer/ray.h"
#include "renderer/registry.h"

namespace isotrace {

/// Where a light is sampled from: a point and, on a surface, its shading
/// normal turned to the side being lit (lights may sample the directions
/// that side sees).
struct LightSampleContext {
    Vec3 p = Vec3::Zero();
    Vec3 n = Vec3::Zero();  ///< unit; zero for a point in space
};

struct LightSample {
    RGB radiance = RGB::Zero();  ///< incident radiance (or intensity / d^2 for delta lights)
    Vec3 direction;              ///< unit, from the shading point towards the light
    Vec3 point = Vec3::Zero();   ///< the sampled point of a light at finite distance
    double distance = 0.0;       ///< to the sampled point; infinity for directional and environment
    double pdf = 0.0;            ///< solid-angle density (1 for delta lights)
    bool isDelta = false;
    /// A light seen in a plane mirror (mirror_image_light.h): the index of
    /// the mirror in Scene::planeMirrors; `point` is then the image of the
    /// point on the light.
    int mirror = -1;
};

class Light {
public:
    virtual ~Light() = default;

    /// Point and directional lights: found only by sampling them. Their
    /// sample() does not depend on u, so callers may skip drawing it.
    virtual bool isDelta() const { return false; }
    /// Lights at infinity, seen by rays that leave the scene.
    virtual bool isInfinite() const { return false; }

    virtual LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const = 0;
    /// Solid-angle density with which sample() picks direction `wi` from
    /// `context`, reaching the light at `onLight` with normal `lightNormal`
    /// (infinite lights: the direction alone matters). Zero for delta lights.
    virtual double pdf(const LightSampleContext& context, const Vec3& wi, const Vec3& onLight,
                       const Vec3& lightNormal) const {
        return 0.0;
    }
    /// How much this light may light `context`: an estimate of the
    /// luminance of its irradiance there, from bounds of distance and
    /// orientation. Lights are chosen for next-event estimation in
    /// proportion to it, so it must be positive wherever the light can
    /// contribute (zero only where it cannot: behind a one-sided emitter,
    /// below the surface's horizon).
    virtual double importance(const LightSampleContext& context) const = 0;
    /// Where the light emits from, how strongly and in which directions, for
    /// the light tree (light_bounds.h); its importance() must be zero
    /// wherever LightBounds::importance of these bounds is. None (the
    /// default) for lights at infinity: they are chosen beside the tree.
    virtual std::optional<LightBounds> bounds() const { return std::nullopt; }
    /// Which side of a plane (through `point`, unit `normal`) the light
    /// gives off light from: +1 wholly in front, -1 wholly behind, 0 across
    /// it or all around (the environment). Lights are imaged in plane
    /// mirrors on their own side only.
    virtual int sideOfPlane(const Vec3& point, const Vec3& normal) const { return 0; }
    /// Radiance arriving along a ray that leaves the scene in direction w.
    virtual RGB escapedRadiance(const Vec3& w) const { return RGB::Zero(); }
    /// The mean radiance of an infinite light over all directions (the
    /// Whitted preview's unshadowed ambient light).
    virtual RGB meanRadiance() const { return RGB::Zero(); }
};

/// An importance as a sampling weight: zero unless finite and positive.
inline double samplingWeight(double importance) { return std::isfinite(importance) && importance > 0 ? importance : 0.0; }

/// An upper bound of cos(a, d') over all directions d' within an angle of
/// sine `sinSlack` of unit direction d (sinSlack >= 1: any direction).
/// Light importances use it to bound the cosines over a light's extent.
inline double cosineBound(const Vec3& a, const Vec3& d, double sinSlack) {
    // cos(theta - slack) for theta > slack, else 1; no trigonometric calls:
    // this runs for every light, or every tree node, a sample weighs.
    if (!(sinSlack < 1)) return 1.0;
    const double cosTheta = std::clamp(a.dot(d), -1.0, 1.0);
    const double cosSlack = std::sqrt(1 - sinSlack * sinSlack);
    if (cosTheta >= cosSlack) return 1.0;
    const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
    return cosTheta * cosSlack + sinTheta * sinSlack;
}
/// The sine of the half-angle that a sphere of radius r at distance
/// `distance` subtends (1 when the point is inside it).
double sphereSinHalfAngle(double r, double distance);

class SceneBuilder;

/// Reads one entry of "lights" (its index given, for names) and adds what
/// it describes to the scene: a light, or emissive geometry sampled as one.
/// The reader is left for the caller to finish.
using LightFactory = void (*)(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
const Registry<LightFactory>& lightRegistry();

}  // namespace isotrace
