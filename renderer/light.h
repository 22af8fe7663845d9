// Light sources. Point and directional lights are delta lights; area lights
// are emissive triangles sampled by area (quads, disks and emissive meshes);
// the environment surrounds the scene. Each type is one file in lights/,
// listed in lights/light_types.cpp.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "renderer/color.h"
#include "renderer/ray.h"
#include "renderer/registry.h"

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
    virtual ~Light() = default;

    /// Point and directional lights: found only by sampling them.
    virtual bool isDelta() const { return false; }
    /// Lights at infinity, seen by rays that leave the scene.
    virtual bool isInfinite() const { return false; }

    virtual LightSample sample(const Vec3& p, const Eigen::Vector2d& u) const = 0;
    /// Solid-angle density with which sample() picks the point `onLight`
    /// (normal `lightNormal`) seen from `p`; infinite lights: the direction
    /// alone matters. Zero for delta lights.
    virtual double pdf(const Vec3& p, const Vec3& onLight, const Vec3& lightNormal) const { return 0.0; }
    /// Radiance arriving along a ray that leaves the scene in direction w.
    virtual RGB escapedRadiance(const Vec3& w) const { return RGB::Zero(); }
    /// The mean radiance of an infinite light over all directions (the
    /// Whitted preview's unshadowed ambient light).
    virtual RGB meanRadiance() const { return RGB::Zero(); }
};

class SceneBuilder;

/// Reads one entry of "lights" (its index given, for names) and adds what
/// it describes to the scene: a light, or emissive geometry sampled as one.
/// The reader is left for the caller to finish.
using LightFactory = void (*)(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
const Registry<LightFactory>& lightRegistry();

}  // namespace isotrace
