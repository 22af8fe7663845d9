// The BSDF interface: what integrators know of a surface's scattering. They
// evaluate, sample and ask densities through it, never by material type.
//
// Directions are world-space unit vectors pointing away from the surface
// (wo towards the viewer, wi towards the light), as in pbrt. Values of
// evaluate() exclude the cosine factor; a sample's weight includes it
// (f cos / pdf, Mitsuba's convention), so a lobe sampled exactly in
// proportion to f cos gives its reflectance without rounding.
#pragma once

#include <cstdint>
#include <optional>

#include "renderer/color.h"
#include "renderer/ray.h"
#include "renderer/sampler.h"

namespace isotrace {

/// The local geometry a BSDF scatters at.
struct ShadingPoint {
    Vec3 position;
    Vec3 geometricNormal;  ///< unit, on the side of wo
    Vec3 shadingNormal;    ///< unit, on the same side as geometricNormal
};

/// Lobe kinds, combined as bits.
enum BSDFFlags : uint32_t {
    kBSDFDiffuseReflection = 1u << 0,
    /// A Dirac delta lobe: evaluate() and pdf() are zero for it, only
    /// sample() finds it, and lights cannot be sampled towards it.
    kBSDFSpecularReflection = 1u << 1,
};

struct BSDFSample {
    Vec3 wi;
    RGB weight = RGB::Zero();  ///< f |cos| / pdf; for a delta lobe its reflectance
    double pdf = 0.0;          ///< solid-angle density; 0 for delta lobes
    bool delta = false;
};

class BSDF {
public:
    virtual ~BSDF() = default;

    virtual uint32_t flags() const = 0;
    /// Every lobe is a delta lobe: next-event estimation cannot help.
    bool isDeltaOnly() const { return (flags() & ~uint32_t(kBSDFSpecularReflection)) == 0; }

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
};

}  // namespace isotrace
