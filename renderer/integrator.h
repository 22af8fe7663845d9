// Light transport: the radiance arriving along a camera ray. Integrators
// see surfaces through their BSDFs and emissions and lights through the
// Light interface, never by type. Each type is one file in integrators/,
// listed in integrators/integrator_types.cpp.
#pragma once

#include <memory>

#include "renderer/color.h"
#include "renderer/interior_stack.h"
#include "renderer/registry.h"
#include "renderer/sampling/sampler.h"
#include "renderer/sampling/sampling.h"
#include "renderer/scene.h"

namespace isotrace {

class Integrator {
public:
    virtual ~Integrator() = default;
    /// The type name of the scene file ("path"), recorded in renders.
    virtual const char* typeName() const = 0;
    virtual RGB radiance(const Scene& scene, const Ray& ray, Sampler& sampler) const = 0;
    /// How the scene's LightSampler chooses lights for this integrator.
    virtual LightSampling lightSampling() const { return LightSampling::Tree; }
};

/// Reads one integrator's keys (the reader is left for the caller to finish).
using IntegratorFactory = std::unique_ptr<Integrator> (*)(geometry::JsonObjectReader& r);
const Registry<IntegratorFactory>& integratorRegistry();
/// The integrator of a scene that names none: path tracing with defaults.
std::unique_ptr<Integrator> makeDefaultIntegrator();

// Shared helpers.

/// Distance to push a ray's origin off a surface at p (relative to p's
/// magnitude, so float positions in Embree do not re-hit the surface).
inline double rayOffset(const Vec3& p) { return 1e-4 * (1.0 + p.cwiseAbs().maxCoeff()); }
/// Origin for a ray leaving a surface at p (geometric normal n) towards w.
inline Vec3 offsetOrigin(const Vec3& p, const Vec3& n, const Vec3& w) {
    return p + (n.dot(w) >= 0 ? 1.0 : -1.0) * rayOffset(p) * n;
}
/// True when nothing blocks a light sample seen from surface point p
/// (geometric normal ng, on the lit side). The shadow ray starts off the
/// surface and, for a light at finite distance, aims at the sampled point
/// from where it starts and ends just short of it: measured from the
/// unshifted point it would reach past a light seen at a grazing angle and
/// hit the light itself.
bool unoccluded(const Scene& scene, const Vec3& p, const Vec3& ng, const LightSample& sample);
/// What of a light sample reaches surface point p: one or zero as
/// unoccluded() finds, or for a light seen in a plane mirror the mirror's
/// reflectance where the sample's ray meets it, when the ray meets the
/// mirror object first and nothing blocks the way from there to the light.
RGB shadowRayWeight(const Scene& scene, const Vec3& p, const Vec3& ng, const LightSample& sample);
/// The shading frame at a hit seen along direction wo: normals turned to
/// wo's side (surfaces are two-sided), the side wo is on, and what
/// textures look up. `footprint` is the world-space width a pixel covers
/// there.
ShadingPoint shadingPointOf(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, double footprint = 0.0);
/// The shading point delta lobes are drawn at: `sp`, or `sp` with its
/// geometric normal for shading normal when wo is behind the shading
/// normal or a lobe about it would leave through the other side of the
/// surface. Shading normals of a polygonized crease lean far from its
/// faces; glass there would otherwise refract light into the side it came
/// from, or lose it.
ShadingPoint deltaShadingPoint(const BSDF& bsdf, const ShadingPoint& sp, const Vec3& wo);
/// The next surface along a path's ray. A hit on a solid the path has met
/// before, from the side the path is not on (entering a solid it is in, or
/// leaving one it is not in), is no crossing: the ray passes through it.
bool nextSurface(const Scene& scene, const Ray& ray, const InteriorStack& interiors, SurfaceHit& hit);
/// The solids `point` is inside (for paths that start there: the camera).
InteriorStack interiorsAt(const Scene& scene, const Vec3& point);
/// Records in `interiors` the side of a solid's surface a path leaving
/// `sp` along wi is on.
void recordSide(const Scene& scene, const SurfaceHit& hit, const ShadingPoint& sp, const Vec3& wi,
                InteriorStack& interiors);
/// Width of a pixel's footprint per unit of path length (the camera's
/// spread angle per pixel; ray cones without curvature).
double pixelSpreadAngle(const Scene& scene);

}  // namespace isotrace
