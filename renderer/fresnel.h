// Fresnel reflectance of smooth interfaces, and refraction by Snell's law.
// Unpolarized light: the mean of the s- and p-polarized reflectances.
#pragma once

#include <optional>

#include "renderer/color.h"
#include "renderer/ray.h"

namespace isotrace {

/// Reflectance of a dielectric interface for light arriving at cosine
/// cosThetaI (> 0: on the side the normal faces) where eta is the index
/// behind the interface over the index in front. 1 under total internal
/// reflection.
double fresnelDielectric(double cosThetaI, double eta);
/// Reflectance of a conductor of complex index eta + i k (relative to the
/// outside medium), per channel.
RGB fresnelConductor(double cosThetaI, const RGB& eta, const RGB& k);
/// The hemispherical average of fresnelDielectric weighted by cos (the
/// fraction of diffuse light an interface reflects): 2 int F(c) c dc.
double fresnelDiffuseReflectance(double eta);
/// Direction of light arriving along -wi through an interface with unit
/// normal n (on wi's side) and relative index eta (behind over front);
/// none under total internal reflection.
std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, double eta);

}  // namespace isotrace
