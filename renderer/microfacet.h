// The Trowbridge-Reitz (GGX) microfacet distribution with Smith's
// height-correlated masking-shadowing, and sampling of the normals visible
// from a direction (Heitz 2018), all in a local frame whose z is the
// macroscopic normal. Rough conductors, dielectrics and coats share it.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "renderer/ray.h"

namespace isotrace {

class TrowbridgeReitz {
public:
    /// Below this alpha a surface is treated as smooth (a delta lobe), as
    /// pbrt does: the distribution is too peaked to sample or evaluate well.
    static constexpr double kSmoothAlpha = 1e-3;
    /// The user's perceptual roughness in [0, 1] to alpha (alpha = r^2,
    /// the convention of Disney's and Blender's principled materials).
    static double alphaFromRoughness(double roughness) { return roughness * roughness; }

    TrowbridgeReitz(double alphaX, double alphaY)
        : alphaX_(std::max(alphaX, 1e-4)), alphaY_(std::max(alphaY, 1e-4)) {}

    bool effectivelySmooth() const { return std::max(alphaX_, alphaY_) < kSmoothAlpha; }

    /// Density of microfacet normals m (projected: integrates D cos over the hemisphere to 1).
    double D(const Vec3& m) const;
    /// Smith's auxiliary function: G1(w) = 1 / (1 + Lambda(w)).
    double lambda(const Vec3& w) const;
    double G1(const Vec3& w) const { return 1.0 / (1.0 + lambda(w)); }
    /// Height-correlated masking-shadowing of the pair.
    double G(const Vec3& wo, const Vec3& wi) const { return 1.0 / (1.0 + lambda(wo) + lambda(wi)); }
    /// Density of the normals visible from w: G1(w) max(0, w.m) D(m) / |w.z|.
    double visibleD(const Vec3& w, const Vec3& m) const;
    /// Draws a normal from visibleD(w, .) (w in the upper hemisphere or not).
    Vec3 sampleVisibleNormal(const Vec3& w, const Eigen::Vector2d& u) const;

private:
    double alphaX_, alphaY_;
};

}  // namespace isotrace
