// "plastic": a diffuse base under a clear dielectric coat (varnish, paint,
// plastic), as Mitsuba 3's plastic and roughplastic. The coat reflects
// F(wo) specularly (a delta lobe, or GGX microfacets when rough); light
// entering it scatters in the base and leaves through the coat, with the
// light the coat reflects back inside accounted for in closed form:
//   f_diffuse = (1 - F(wi)) (1 - F(wo)) albedo / (pi eta^2 (1 - Fdr_inside)),
// Fdr_inside being the coat's internal diffuse reflectance. A white smooth
// plastic reflects all light exactly (eta^2 (1 - Fdr_inside) = 1 - Fdr_outside);
// a rough one loses what its microfacets lose. With multiple scattering
// (the default), the rough coat's own albedo C(mu), which its single-
// scattering facets make less than F(mu), takes F's place:
//   f_diffuse = (1 - C(wi)) (1 - C(wo)) albedo / (pi (1 - C_avg)),
// so a white rough plastic reflects all light too.
#include <cmath>
#include <numbers>

#include "renderer/fresnel.h"
#include "renderer/material.h"
#include "renderer/microfacet.h"
#include "renderer/microfacet_albedo.h"
#include "renderer/sampling/sampling.h"

namespace isotrace {

namespace {

class PlasticBSDF final : public BSDF {
public:
    PlasticBSDF(ColorParameter albedo, double ior, ScalarParameter roughness, bool multipleScattering)
        : albedo_(std::move(albedo)), ior_(ior), roughness_(std::move(roughness)) {
        const double alpha = TrowbridgeReitz::alphaFromRoughness(roughness_.maximum());
        smooth_ = TrowbridgeReitz(alpha, alpha).effectivelySmooth();
        diffuseScale_ = 1.0 / (ior_ * ior_ * (1.0 - fresnelDiffuseReflectance(1.0 / ior_)));
        if (!smooth_ && multipleScattering) coatAlbedo_ = dielectricAlbedo(ior_, roughness_.minimum(), roughness_.maximum());
    }

    uint32_t flags() const override {
        return kBSDFDiffuseReflection | (smooth_ ? kBSDFSpecularReflection : kBSDFGlossyReflection);
    }

    RGB evaluate(const ShadingPoint& p, const Vec3& woWorld, const Vec3& wiWorld) const override {
        const Frame frame(p.shadingNormal);
        return valueLocal(p, frame.toLocal(woWorld), frame.toLocal(wiWorld));
    }
    double pdf(const ShadingPoint& p, const Vec3& woWorld, const Vec3& wiWorld) const override {
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld);
        return wo.z() > 0 ? pdfLocal(p, wo, frame.toLocal(wiWorld), specularProbability(p, wo)) : 0.0;
    }
    std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& woWorld, Sampler& sampler) const override {
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld);
        const double uChoice = sampler.get1D();
        const Eigen::Vector2d u = sampler.get2D();
        if (!(wo.z() > 0)) return std::nullopt;
        const double pSpecular = specularProbability(p, wo);
        BSDFSample s;
        if (uChoice < pSpecular) {
            if (smooth_) {
                s.wi = reflect(-woWorld, p.shadingNormal);
                s.weight = RGB::Constant(fresnelDielectric(wo.z(), ior_) / pSpecular);
                s.delta = true;
                return s;
            }
            const Vec3 m = distribution(p).sampleVisibleNormal(wo, u);
            s.wi = frame.toWorld(reflect(-wo, m));
        } else {
            s.wi = sampleCosineHemisphere(p.shadingNormal, u);
        }
        const double cosTheta = p.shadingNormal.dot(s.wi);
        if (!(cosTheta > 0)) return std::nullopt;
        // In this frame, with the probability already found.
        const Vec3 wi = frame.toLocal(s.wi);
        s.pdf = pdfLocal(p, wo, wi, pSpecular);
        if (!(s.pdf > 0)) return std::nullopt;
        s.weight = valueLocal(p, wo, wi) * (cosTheta / s.pdf);
        return s;
    }
    int deltaLobes(const ShadingPoint& p, const Vec3& wo, BSDFSample lobes[2]) const override {
        const double cosTheta = p.shadingNormal.dot(wo);
        if (!smooth_ || !(cosTheta > 0)) return 0;
        lobes[0].wi = reflect(-wo, p.shadingNormal);
        lobes[0].weight = RGB::Constant(fresnelDielectric(cosTheta, ior_));
        lobes[0].delta = true;
        return 1;
    }
    RGB albedo(const ShadingPoint& p) const override { return albedo_.at(p); }

private:
    RGB valueLocal(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const {
        if (!(wo.z() > 0 && wi.z() > 0)) return RGB::Zero();
        RGB f = diffuse(p, wo, wi);
        if (!smooth_) f += RGB::Constant(specular(p, wo, wi));
        return f;
    }
    double pdfLocal(const ShadingPoint& p, const Vec3& wo, const Vec3& wi, double pSpecular) const {
        if (!(wo.z() > 0 && wi.z() > 0)) return 0.0;
        double density = (1.0 - pSpecular) * wi.z() / std::numbers::pi;
        if (!smooth_) density += pSpecular * specularPdf(p, wo, wi);
        return density;
    }
    TrowbridgeReitz distribution(const ShadingPoint& p) const {
        const double alpha =
            std::max(TrowbridgeReitz::alphaFromRoughness(roughness_.at(p)), TrowbridgeReitz::kSmoothAlpha);
        return TrowbridgeReitz(alpha, alpha);
    }
    RGB diffuse(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const {
        if (coatAlbedo_) {
            const MicrofacetAlbedoTable& coat = coatAlbedo_->reflectedOutside;
            const double r = roughness_.at(p);
            const double through = (1.0 - coat.at(wi.z(), r)) * (1.0 - coat.at(wo.z(), r));
            return albedo_.at(p) * (through / (std::numbers::pi * (1.0 - coat.average(r))));
        }
        const double through = (1.0 - fresnelDielectric(wi.z(), ior_)) * (1.0 - fresnelDielectric(wo.z(), ior_));
        return albedo_.at(p) * (through * diffuseScale_ / std::numbers::pi);
    }
    double specular(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const {
        const Vec3 m = (wo + wi).normalized();
        const TrowbridgeReitz d = distribution(p);
        return d.D(m) * d.G(wo, wi) * fresnelDielectric(wo.dot(m), ior_) / (4.0 * wo.z() * wi.z());
    }
    double specularPdf(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const {
        const Vec3 m = (wo + wi).normalized();
        return distribution(p).visibleD(wo, m) / (4.0 * wo.dot(m));
    }
    /// The coat's share of what is reflected towards wo, so a dark base
    /// sends most samples to the coat and a white smooth one gives every
    /// sample weight 1.
    double specularProbability(const ShadingPoint& p, const Vec3& wo) const {
        const double F = fresnelDielectric(wo.z(), ior_);
        const double base = (1.0 - F) * albedo_.at(p).mean();
        return F + base > 0 ? F / (F + base) : 1.0;
    }

    ColorParameter albedo_;
    double ior_;
    ScalarParameter roughness_;
    bool smooth_ = true;
    double diffuseScale_ = 1.0;  ///< 1 / (eta^2 (1 - Fdr_inside))
    std::shared_ptr<const DielectricAlbedo> coatAlbedo_;  ///< with multiple scattering
};

}  // namespace

Material readPlasticMaterial(geometry::JsonObjectReader& r, const MaterialContext& context) {
    ColorParameter albedo = readColorParameter(r, "albedo", RGB::Constant(0.5), context, 0.0, 1.0);
    const double ior = r.number("ior", 1.5);
    if (!(ior > 1) || !std::isfinite(ior)) r.fail("ior", "the coat's index of refraction must be above 1");
    if (ior > 10) r.fail("ior", "must be at most 10 (diamond is 2.42)");
    Material m;
    ScalarParameter roughness = readScalarParameter(r, "roughness", 0.0, context, 0.0, 1.0);
    m.bsdf = std::make_shared<PlasticBSDF>(std::move(albedo), ior, std::move(roughness),
                                           r.boolean("multiple_scattering", true));
    return m;
}

}  // namespace isotrace
