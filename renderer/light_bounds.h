// What the light tree (light_tree.h) knows of a light at finite distance, or
// of a cluster of them: where they emit from, how strongly, and towards
// which directions, after Conty Estevez and Kulla, "Importance Sampling of
// Many Lights with Adaptive Tree Splitting" (2018). The directions are a
// cone of surface normals (axis, spread theta_o) and, around each normal,
// the angle theta_e within which light leaves it (pi/2 for a diffuse
// emitter, the cone angle for a spot light).
#pragma once

#include "geometry/bounding_box.h"
#include "renderer/ray.h"

namespace isotrace {

struct LightSampleContext;

struct LightBounds {
    geometry::Box3 box;      ///< holds every emitting point
    /// Scales the importance: L A for an emitter of radiance L and area A,
    /// I for a point source (luminances), so that importance() estimates
    /// irradiance as Light::importance does.
    double power = 0.0;
    Vec3 axis = Vec3(0, 0, 1);        ///< unit
    double cosNormalSpread = 1.0;     ///< cos theta_o; -1: normals in every direction
    double cosEmissionSpread = 0.0;   ///< cos theta_e
    bool twoSided = false;            ///< emits along -normal too

    /// An upper estimate of the irradiance that lights within these bounds
    /// give `context`: power cos(theta') cos(theta'_i) / d^2 with the angles
    /// bounded over the box. Zero only where no light within them can
    /// light the context (behind every normal's emission, or below the
    /// receiver's horizon).
    double importance(const LightSampleContext& context) const;
    /// The orientation measure M_Omega of the paper: the solid angle the
    /// cone of emission covers, weighted by cosine. The tree's build cost.
    double orientationMeasure() const;
};

/// LightBounds with what importance() needs at every call worked out once:
/// the light tree's nodes, weighed at every sample.
struct PreparedLightBounds {
    Vec3 center = Vec3::Zero(), halfExtent = Vec3::Zero(), axis = Vec3(0, 0, 1);
    double radius = 0.0;  ///< of the sphere around the box
    double power = 0.0;
    double cosNormalSpread = 1.0, sinNormalSpread = 0.0, cosEmissionSpread = 0.0;
    bool twoSided = false;

    PreparedLightBounds() = default;
    explicit PreparedLightBounds(const LightBounds& bounds);
    /// LightBounds::importance.
    double importance(const LightSampleContext& context) const;
};

/// Bounds that hold both: boxes and powers summed, cones merged.
LightBounds unite(const LightBounds& a, const LightBounds& b);

/// The bounds of a point source of intensity luminance `intensity`
/// emitting in every direction (theta_o = pi, theta_e = pi/2).
LightBounds pointSourceBounds(const Vec3& position, double intensity);

}  // namespace isotrace
