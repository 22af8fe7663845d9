// "dielectric": glass, water, clear plastic. Exact Fresnel reflection and
// Snell refraction, smooth (two delta lobes) or rough (GGX microfacets after
// Walter et al. 2007, visible-normal sampling), or `thin`: a sheet whose two
// faces reflect and transmit without bending the ray (windows, bubbles).
// Which side is inside comes from the shading point: rays travelling inside
// a solid see the inverse index. Refracted radiance carries 1 / eta^2.
//
// Rough glass adds back what single scattering between facets loses
// (Kulla and Conty 2017) with reciprocal cosine-like lobes: on the side s
// of wo, (1 - E_s(mu_o)) (1 - E_s'(mu_i)) times a constant per pair of
// sides, E_s being the single-scattering albedo seen from s. The constants
// make the albedo 1 from both sides at once; of the light it adds from
// outside, the share 1 - F_avg (the smooth interface's) is refracted.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "renderer/fresnel.h"
#include "renderer/material.h"
#include "renderer/microfacet.h"
#include "renderer/microfacet_albedo.h"
#include "renderer/sampling/sampling.h"

namespace isotrace {

namespace {

class DielectricBSDF final : public BSDF {
public:
    DielectricBSDF(double ior, ScalarParameter roughness, ColorParameter transmittance, bool thin,
                   bool multipleScattering)
        : ior_(ior), roughness_(std::move(roughness)), transmittance_(std::move(transmittance)), thin_(thin) {
        const double alpha = TrowbridgeReitz::alphaFromRoughness(roughness_.maximum());
        smooth_ = thin_ || TrowbridgeReitz(alpha, alpha).effectivelySmooth();
        if (!smooth_ && multipleScattering && ior_ != 1.0)
            albedo_ = dielectricAlbedo(ior_, roughness_.minimum(), roughness_.maximum());
    }

    uint32_t flags() const override {
        return smooth_ ? kBSDFSpecularReflection | kBSDFSpecularTransmission
                       : kBSDFGlossyReflection | kBSDFGlossyTransmission;
    }

    RGB evaluate(const ShadingPoint& p, const Vec3& woWorld, const Vec3& wiWorld) const override {
        if (smooth_) return RGB::Zero();
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld), wi = frame.toLocal(wiWorld);
        return roughLobe(p, wo, wi, distribution(p)).value + multipleLobe(p, wo).value(p, wi, transmittance_);
    }
    double pdf(const ShadingPoint& p, const Vec3& woWorld, const Vec3& wiWorld) const override {
        if (smooth_) return 0.0;
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld), wi = frame.toLocal(wiWorld);
        const MultipleLobe multiple = multipleLobe(p, wo);
        return (1.0 - multiple.probability) * roughLobe(p, wo, wi, distribution(p)).pdf + multiple.pdf(wi);
    }
    std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& woWorld, Sampler& sampler) const override {
        const double uChoice = sampler.get1D();
        if (smooth_) {
            BSDFSample lobes[2];
            const int count = deltaLobes(p, woWorld, lobes);
            if (count == 0) return std::nullopt;
            // Choose reflection or transmission by their share of the energy,
            // so a colourless path keeps weight 1.
            const double reflect = lobes[0].weight.maxCoeff();
            const double transmit = count > 1 ? lobes[1].weight.maxCoeff() * square(lobes[1].etaRatio) : 0.0;
            const double total = reflect + transmit;
            if (!(total > 0)) return std::nullopt;
            const bool chooseReflection = uChoice * total < reflect;
            BSDFSample s = lobes[chooseReflection ? 0 : 1];
            s.weight /= (chooseReflection ? reflect : transmit) / total;
            return s;
        }
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld);
        const Eigen::Vector2d u = sampler.get2D();
        if (!(wo.z() > 0)) return std::nullopt;
        const double eta = relativeIndex(p);
        const TrowbridgeReitz d = distribution(p);
        const MultipleLobe multiple = multipleLobe(p, wo);
        Vec3 wi;
        if (uChoice < multiple.probability) {
            // The multiple-scattering lobes: refracted with their share.
            const double v = uChoice / multiple.probability;
            wi = sampleCosineHemisphere(Vec3(0, 0, 1), u);
            if (v < multiple.refractedShare) wi.z() = -wi.z();
        } else {
            const double v = (uChoice - multiple.probability) / (1.0 - multiple.probability);
            const Vec3 m = d.sampleVisibleNormal(wo, u);
            const double F = fresnelDielectric(wo.dot(m), eta);
            if (v < F) {
                wi = reflect(-wo, m);
                if (!(wi.z() > 0)) return std::nullopt;
            } else {
                const std::optional<Vec3> t = refract(wo, m, eta);
                if (!t || !(t->z() < 0)) return std::nullopt;
                wi = *t;
            }
        }
        // Value and density of the pair in one pass, with this frame and
        // distribution (the roughness texture looked up once).
        const RoughLobe lobe = roughLobe(p, wo, wi, d);
        BSDFSample s;
        s.wi = frame.toWorld(wi);
        s.pdf = (1.0 - multiple.probability) * lobe.pdf + multiple.pdf(wi);
        if (!(s.pdf > 0)) return std::nullopt;
        s.weight = (lobe.value + multiple.value(p, wi, transmittance_)) * (std::abs(wi.z()) / s.pdf);
        s.etaRatio = wi.z() < 0 ? eta : 1.0;
        return s;
    }
    int deltaLobes(const ShadingPoint& p, const Vec3& wo, BSDFSample lobes[2]) const override {
        if (!smooth_) return 0;
        const Vec3& n = p.shadingNormal;
        const double cosTheta = n.dot(wo);
        if (!(cosTheta > 0)) return 0;
        lobes[0].wi = reflect(-wo, n);
        lobes[0].delta = true;
        lobes[1].delta = true;
        if (thin_) {
            // Light bounces between the sheet's faces: R' = R + T^2 R / (1 - R^2).
            double R = fresnelDielectric(cosTheta, ior_);
            const double T = 1.0 - R;
            if (R < 1) R += T * T * R / (1 - R * R);
            lobes[0].weight = RGB::Constant(R);
            lobes[1].wi = -wo;
            lobes[1].weight = transmittance_.at(p) * (1.0 - R);
            return 2;
        }
        const double eta = relativeIndex(p);
        const double R = fresnelDielectric(cosTheta, eta);
        lobes[0].weight = RGB::Constant(R);
        const std::optional<Vec3> t = refract(wo, n, eta);
        if (!t || R >= 1.0) return 1;  // total internal reflection
        lobes[1].wi = *t;
        lobes[1].weight = transmittance_.at(p) * ((1.0 - R) / (eta * eta));
        lobes[1].etaRatio = eta;
        return 2;
    }
    RGB albedo(const ShadingPoint& p) const override { return transmittance_.at(p); }
    double solidIndex() const override { return thin_ ? 0.0 : ior_; }

private:
    static double square(double x) { return x * x; }

    /// The multiple-scattering lobes seen from wo, on wo's side ("here")
    /// and across ("there").
    struct MultipleLobe {
        const DielectricAlbedo* albedo = nullptr;
        bool outside = true;
        double roughness = 0.0;
        double reflected = 0.0, refracted = 0.0;  ///< value before (1 - E(mu_i)) of each
        double probability = 0.0;                 ///< of sampling them
        double refractedShare = 0.0;              ///< of those samples
        const MicrofacetAlbedoTable& table(bool outsideSide) const {
            return outsideSide ? albedo->outside : albedo->inside;
        }
        RGB value(const ShadingPoint& p, const Vec3& wi, const ColorParameter& transmittance) const {
            if (!albedo || wi.z() == 0) return RGB::Zero();
            const double mu = std::abs(wi.z());
            if (wi.z() > 0) return RGB::Constant(reflected * (1.0 - table(outside).at(mu, roughness)));
            return transmittance.at(p) * (refracted * (1.0 - table(!outside).at(mu, roughness)));
        }
        double pdf(const Vec3& wi) const {
            if (!(probability > 0)) return 0.0;
            const double share = wi.z() > 0 ? 1.0 - refractedShare : refractedShare;
            return probability * share * std::abs(wi.z()) / std::numbers::pi;
        }
    };
    MultipleLobe multipleLobe(const ShadingPoint& p, const Vec3& wo) const {
        MultipleLobe lobe;
        if (!albedo_) return lobe;
        const double r = roughness_.at(p);
        const double lostOutside = 1.0 - albedo_->outside.average(r), lostInside = 1.0 - albedo_->inside.average(r);
        if (!(lostOutside > 1e-6 && lostInside > 1e-6)) return lobe;
        // Shares refracted of what is added back, from each side: energy
        // from inside is 1 when c_Ri pi lostInside + c_T pi lostOutside = 1,
        // from outside when c_Ro pi lostOutside + n^2 c_T pi lostInside = 1,
        // with c_T the constant of refraction from outside (reciprocity
        // makes the other n^2 c_T).
        const double n2 = ior_ * ior_;
        double shareOutside = 1.0 - albedo_->fresnelAverageOutside;
        double shareInside = shareOutside * lostOutside / (n2 * lostInside);
        if (shareInside > 1.0) {
            shareOutside /= shareInside;
            shareInside = 1.0;
        }
        const double pi = std::numbers::pi;
        const double cT = shareOutside / (n2 * pi * lostInside);
        const double lostHere = 1.0 - (p.outside ? albedo_->outside : albedo_->inside).at(wo.z(), r);
        lobe.albedo = albedo_.get();
        lobe.outside = p.outside;
        lobe.roughness = r;
        lobe.reflected = lostHere * (p.outside ? (1.0 - shareOutside) / (pi * lostOutside)
                                               : (1.0 - shareInside) / (pi * lostInside));
        lobe.refracted = lostHere * (p.outside ? cT : n2 * cT);
        lobe.probability = std::clamp(lostHere, 0.0, 1.0);
        lobe.refractedShare = p.outside ? shareOutside : shareInside;
        return lobe;
    }
    /// The index across the surface over the index on wo's side.
    double relativeIndex(const ShadingPoint& p) const { return p.outside ? ior_ : 1.0 / ior_; }
    TrowbridgeReitz distribution(const ShadingPoint& p) const {
        const double alpha =
            std::max(TrowbridgeReitz::alphaFromRoughness(roughness_.at(p)), TrowbridgeReitz::kSmoothAlpha);
        return TrowbridgeReitz(alpha, alpha);
    }
    struct RoughLobe {
        RGB value = RGB::Zero();  ///< f(wo, wi)
        double pdf = 0.0;
    };
    /// f and the sampling density of a rough pair, in the local frame.
    RoughLobe roughLobe(const ShadingPoint& p, const Vec3& wo, const Vec3& wi, const TrowbridgeReitz& d) const {
        RoughLobe lobe;
        Vec3 m;
        double eta;
        if (!halfVector(p, wo, wi, m, eta)) return lobe;
        const double F = fresnelDielectric(wo.dot(m), eta);
        if (wi.z() > 0) {
            lobe.value = RGB::Constant(d.D(m) * d.G(wo, wi) * F / (4.0 * wo.z() * wi.z()));
            lobe.pdf = d.visibleD(wo, m) / (4.0 * std::abs(wo.dot(m))) * F;
            return lobe;
        }
        const double denominator = square(wi.dot(m) + wo.dot(m) / eta);
        const double value = d.D(m) * d.G(wo, wi) * (1.0 - F) * std::abs(wi.dot(m) * wo.dot(m)) /
                             (std::abs(wi.z() * wo.z()) * denominator) / (eta * eta);
        lobe.value = transmittance_.at(p) * value;
        lobe.pdf = d.visibleD(wo, m) * std::abs(wi.dot(m)) / denominator * (1.0 - F);
        return lobe;
    }
    /// The microfacet normal taking wo to wi (by reflection or refraction),
    /// facing wo's side; false for pairs no facet connects.
    bool halfVector(const ShadingPoint& p, const Vec3& wo, const Vec3& wi, Vec3& m, double& eta) const {
        if (!(wo.z() > 0) || wi.z() == 0) return false;
        eta = relativeIndex(p);
        const bool reflection = wi.z() > 0;
        m = reflection ? Vec3(wi + wo) : Vec3(wi * eta + wo);
        if (!(m.squaredNorm() > 0)) return false;
        m.normalize();
        if (m.z() < 0) m = -m;
        // Facets seen from behind by either direction contribute nothing.
        if (m.dot(wo) <= 0 || m.dot(wi) * wi.z() <= 0) return false;
        return true;
    }

    double ior_;
    ScalarParameter roughness_;
    ColorParameter transmittance_;
    bool thin_;
    bool smooth_ = true;
    std::shared_ptr<const DielectricAlbedo> albedo_;  ///< with multiple scattering
};

}  // namespace

Material readDielectricMaterial(geometry::JsonObjectReader& r, const MaterialContext& context) {
    const double ior = r.number("ior", 1.5);
    if (!(ior > 0) || !std::isfinite(ior)) r.fail("ior", "the index of refraction must be positive");
    if (ior > 10) r.fail("ior", "must be at most 10 (diamond is 2.42)");
    const bool thin = r.boolean("thin", false);
    ScalarParameter roughness = readScalarParameter(r, "roughness", 0.0, context, 0.0, 1.0);
    if (thin && roughness.maximum() > 0) r.fail("roughness", "a thin dielectric is smooth: roughness must be 0");
    Material m;
    ColorParameter transmittance = readColorParameter(r, "transmittance", RGB::Ones(), context, 0.0, 1.0);
    m.bsdf = std::make_shared<DielectricBSDF>(ior, std::move(roughness), std::move(transmittance), thin,
                                              r.boolean("multiple_scattering", true));
    return m;
}

}  // namespace isotrace
