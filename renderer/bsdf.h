// The BSDF interface: what integrators know of a surface's scattering. They
// evaluate, sample and ask densities through it, never by material type.
//
// Directions are world-space unit vectors pointing away from the surface
// (wo towards the viewer, wi towards the light), as in pbrt. Values of
// evaluate() exclude the cosine factor; a sample's weight includes it
// (f cos / pdf, Mitsuba's convention), so a lobe sampled exactly in
// proportion to f cos gives its reflectance without rounding. Light
// refracted into a medium of relative index eta carries radiance scaled by
// 1 / eta^2 (pbrt's radiance transport mode), so f is reciprocal only up to
// that factor.
#pragma once

#include <cstdint>
#include <optional>

#include "renderer/color.h"
#include "renderer/ray.h"
#include "renderer/sampling/sampler.h"

namespace isotrace {

/// The local geometry a BSDF scatters at, and what textures look up.
struct ShadingPoint {
    Vec3 position;
    Vec3 geometricNormal;  ///< unit, on the side of wo
    Vec3 shadingNormal;    ///< unit, on the same side as geometricNormal
    /// wo lies on the side the surface's outward normal faces (for implicit
    /// surfaces where the field is positive; for meshes, the side their
    /// winding faces). False for a ray travelling inside a solid.
    bool outside = true;
    /// The point and outward normal in the object's own space, where solid
    /// and projected textures are defined (they follow the object's transform).
    Vec3 objectPosition = Vec3::Zero();
    Vec3 objectNormal = Vec3(0, 0, 1);
    /// Width of the pixel's footprint at the point, in object space (zero:
    /// a point lookup), so image textures filter over what a pixel sees.
    double footprint = 0.0;
    /// Texture coordinates, on meshes that have them, and the footprint's width in them.
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    bool hasUv = false;
    double uvFootprint = 0.0;
};

/// Lobe kinds, combined as bits.
enum BSDFFlags : uint32_t {
    kBSDFDiffuseReflection = 1u << 0,
    /// A Dirac delta lobe: evaluate() and pdf() are zero for it, only
    /// sample() finds it, and lights cannot be sampled towards it.
    kBSDFSpecularReflection = 1u << 1,
    kBSDFGlossyReflection = 1u << 2,
    kBSDFSpecularTransmission = 1u << 3,
    kBSDFGlossyTransmission = 1u << 4,
};
constexpr uint32_t kBSDFSpecular = kBSDFSpecularReflection | kBSDFSpecularTransmission;
constexpr uint32_t kBSDFTransmission = kBSDFSpecularTransmission | kBSDFGlossyTransmission;

struct BSDFSample {
    Vec3 wi;
    RGB weight = RGB::Zero();  ///< f |cos| / pdf; for a delta lobe its reflectance
    double pdf = 0.0;          ///< solid-angle density; 0 for delta lobes
    bool delta = false;
    /// For a refraction, the ratio of the indices of refraction across the
    /// surface to those on wo's side (1 for reflections). Radiance is
    /// scaled by its inverse square, which Russian roulette should not see.
    double etaRatio = 1.0;
};

class BSDF {
public:
    virtual ~BSDF() = default;

    virtual uint32_t flags() const = 0;
    /// Every lobe is a delta lobe: next-event estimation cannot help.
    bool isDeltaOnly() const { return (flags() & ~kBSDFSpecular) == 0; }
    /// Light may pass through: directions below the surface count, and
    /// lights behind it may be sampled.
    bool transmits() const { return (flags() & kBSDFTransmission) != 0; }
    /// The index of refraction of the solid the surface bounds (glass, not
    /// a thin sheet), whose inside paths keep track of; 0 for surfaces
    /// without one.
    virtual double solidIndex() const { return 0.0; }

    /// f(wo, wi), without the cosine.
    virtual RGB evaluate(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const = 0;
    /// Density with which sample() returns wi, in solid angle.
    virtual double pdf(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const = 0;
    /// Draws a direction. The BSDF takes from `sampler` only the dimensions
    /// it uses (none for a mirror), so a path's later bounces see the same
    /// numbers whatever the lobes before them needed. Empty when the
    /// sample carries no energy.
    virtual std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& wo, Sampler& sampler) const = 0;
    /// The fraction of light it reflects (for albedo AOVs and the Whitted
    /// preview's ambient term).
    virtual RGB albedo(const ShadingPoint& p) const = 0;
    /// Every delta lobe at once, for integrators that split rather than
    /// sample (the Whitted preview follows both the reflection and the
    /// refraction of glass). Writes at most two; returns how many.
    virtual int deltaLobes(const ShadingPoint& p, const Vec3& wo, BSDFSample lobes[2]) const { return 0; }
};

}  // namespace isotrace
