// "conductor": metals. Fresnel reflectance of a complex index of refraction
// (per channel: a named measured metal, explicit eta and k, or a plain
// normal-incidence `reflectance`), smooth (a delta lobe) or rough (GGX
// microfacets, Smith shadowing, visible-normal sampling). What single
// scattering between facets loses is added back by a second, diffuse-like
// lobe (Kulla and Conty 2017): F_ms (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 -
// E_avg)), E being the single-scattering albedo and F_ms the colour of light
// after several facets, F_avg^2 E_avg / (1 - F_avg (1 - E_avg)).
#include <cmath>
#include <map>
#include <numbers>

#include "renderer/fresnel.h"
#include "renderer/material.h"
#include "renderer/microfacet.h"
#include "renderer/microfacet_albedo.h"
#include "renderer/sampling/sampling.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

struct ComplexIndex {
    RGB eta, k;
};

// RGB samples (650, 550, 450 nm) of measured n, k from RefractiveIndex.INFO's
// selection for rendering (gold, silver, copper, aluminium: Rakic 1998 and
// Johnson & Christy 1972 fits; chromium: Johnson & Christy 1974).
const std::map<std::string, ComplexIndex>& metals() {
    static const std::map<std::string, ComplexIndex> table = {
        {"gold", {RGB(0.18299, 0.42108, 1.37340), RGB(3.42420, 2.34590, 1.77040)}},
        {"silver", {RGB(0.15943, 0.14512, 0.13547), RGB(3.92910, 3.19000, 2.38080)}},
        {"copper", {RGB(0.27105, 0.67693, 1.31640), RGB(3.60920, 2.62480, 2.29210)}},
        {"aluminium", {RGB(1.34560, 0.96521, 0.61722), RGB(7.47460, 6.39950, 5.30310)}},
        {"chromium", {RGB(3.64000, 2.90080, 1.99060), RGB(4.35110, 4.23110, 3.75050)}},
    };
    return table;
}

class ConductorBSDF final : public BSDF {
public:
    // The index is either fixed (eta, k) or follows a reflectance texture.
    ConductorBSDF(std::optional<ComplexIndex> index, ColorParameter reflectance, ScalarParameter roughness,
                  bool multipleScattering)
        : index_(index), reflectance_(std::move(reflectance)), roughness_(std::move(roughness)) {
        smooth_ = TrowbridgeReitz(alphaOf(roughness_.maximum()), alphaOf(roughness_.maximum())).effectivelySmooth();
        if (!smooth_ && multipleScattering) albedo_ = &conductorAlbedo(roughness_.minimum(), roughness_.maximum());
        // A fixed index or reflectance has one hemispherical Fresnel
        // average: found once, not at every shading point.
        if (albedo_ && (index_ || (reflectance_.minimum() == reflectance_.maximum()).all()))
            fixedFresnelAverage_ = hemisphericalFresnel(ShadingPoint{});
    }

    uint32_t flags() const override { return smooth_ ? kBSDFSpecularReflection : kBSDFGlossyReflection; }

    RGB evaluate(const ShadingPoint& p, const Vec3& woWorld, const Vec3& wiWorld) const override {
        if (smooth_) return RGB::Zero();
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld), wi = frame.toLocal(wiWorld);
        if (!(wo.z() > 0 && wi.z() > 0)) return RGB::Zero();
        return singleValue(p, wo, wi) + multipleLobe(p, wo).value(wi);
    }
    double pdf(const ShadingPoint& p, const Vec3& woWorld, const Vec3& wiWorld) const override {
        if (smooth_) return 0.0;
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld), wi = frame.toLocal(wiWorld);
        if (!(wo.z() > 0 && wi.z() > 0)) return 0.0;
        return pdfLocal(p, wo, wi, multipleLobe(p, wo));
    }
    std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& woWorld, Sampler& sampler) const override {
        if (smooth_) {
            BSDFSample lobes[2];
            deltaLobes(p, woWorld, lobes);
            return lobes[0];
        }
        const Frame frame(p.shadingNormal);
        const Vec3 wo = frame.toLocal(woWorld);
        const Eigen::Vector2d u = sampler.get2D();
        if (!(wo.z() > 0)) return std::nullopt;
        const TrowbridgeReitz d = distribution(p);
        const MultipleLobe multiple = multipleLobe(p, wo);
        if (!multiple.active()) {
            const Vec3 m = d.sampleVisibleNormal(wo, u);
            const Vec3 wi = reflect(-wo, m);
            if (!(wi.z() > 0)) return std::nullopt;
            BSDFSample s;
            s.wi = frame.toWorld(wi);
            s.pdf = d.visibleD(wo, m) / (4.0 * wo.dot(m));
            if (!(s.pdf > 0)) return std::nullopt;
            // f cos / pdf = F G / G1(wo): the D terms cancel.
            s.weight = fresnel(p, wo.dot(m)) * (d.G(wo, wi) / d.G1(wo));
            return s;
        }
        // The lobe is chosen by the first coordinate, stretched back to [0, 1).
        Eigen::Vector2d v = u;
        Vec3 wi;
        if (u[0] < multiple.probability) {
            v[0] = u[0] / multiple.probability;
            wi = sampleCosineHemisphere(Vec3(0, 0, 1), v);
        } else {
            v[0] = (u[0] - multiple.probability) / (1.0 - multiple.probability);
            wi = reflect(-wo, d.sampleVisibleNormal(wo, v));
        }
        if (!(wi.z() > 0)) return std::nullopt;
        BSDFSample s;
        s.wi = frame.toWorld(wi);
        s.pdf = pdfLocal(p, wo, wi, multiple);
        if (!(s.pdf > 0)) return std::nullopt;
        s.weight = (singleValue(p, wo, wi) + multiple.value(wi)) * (wi.z() / s.pdf);
        return s;
    }
    int deltaLobes(const ShadingPoint& p, const Vec3& wo, BSDFSample lobes[2]) const override {
        if (!smooth_) return 0;
        lobes[0].wi = reflect(-wo, p.shadingNormal);
        lobes[0].weight = fresnel(p, p.shadingNormal.dot(wo));
        lobes[0].delta = true;
        return 1;
    }
    RGB albedo(const ShadingPoint& p) const override { return fresnel(p, 1.0); }

private:
    /// The multiple-scattering lobe seen from wo: a cosine-like lobe of
    /// colour F_ms (1 - E(mu_o)) / (pi (1 - E_avg)) times (1 - E(mu_i)),
    /// sampled with `probability`.
    struct MultipleLobe {
        RGB colour = RGB::Zero();
        const MicrofacetAlbedoTable* albedo = nullptr;
        double roughness = 0.0;
        double probability = 0.0;
        bool active() const { return probability > 0; }
        RGB value(const Vec3& wi) const {
            return active() ? RGB(colour * (1.0 - albedo->at(wi.z(), roughness))) : RGB::Zero();
        }
    };
    MultipleLobe multipleLobe(const ShadingPoint& p, const Vec3& wo) const {
        MultipleLobe lobe;
        if (!albedo_) return lobe;
        lobe.albedo = albedo_;
        lobe.roughness = roughness_.at(p);
        const double E = albedo_->at(wo.z(), lobe.roughness), average = albedo_->average(lobe.roughness);
        if (!(1.0 - average > 1e-6)) return lobe;
        const RGB fresnelAverage = fixedFresnelAverage_ ? *fixedFresnelAverage_ : hemisphericalFresnel(p);
        const RGB colour = fresnelAverage * fresnelAverage * average / (1.0 - fresnelAverage * (1.0 - average));
        lobe.colour = colour * ((1.0 - E) / (std::numbers::pi * (1.0 - average)));
        // By each lobe's share of the light reflected towards wo.
        const double multiple = colour.mean() * (1.0 - E), single = fresnel(p, wo.z()).mean() * E;
        lobe.probability = multiple > 0 ? multiple / (multiple + single) : 0.0;
        return lobe;
    }
    RGB singleValue(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const {
        const Vec3 m = (wo + wi).normalized();
        const TrowbridgeReitz d = distribution(p);
        return fresnel(p, wo.dot(m)) * (d.D(m) * d.G(wo, wi) / (4.0 * wo.z() * wi.z()));
    }
    double pdfLocal(const ShadingPoint& p, const Vec3& wo, const Vec3& wi, const MultipleLobe& multiple) const {
        const Vec3 m = (wo + wi).normalized();
        const double single = distribution(p).visibleD(wo, m) / (4.0 * wo.dot(m));
        return (1.0 - multiple.probability) * single + multiple.probability * wi.z() / std::numbers::pi;
    }
    /// 2 int F(mu) mu dmu, by 8-point Gauss-Legendre quadrature (the
    /// reflectance is smooth in mu).
    RGB hemisphericalFresnel(const ShadingPoint& p) const {
        static constexpr double kNodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                             0.9602898564975363};
        static constexpr double kWeights[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                               0.1012285362903763};
        RGB sum = RGB::Zero();
        for (int i = 0; i < 4; ++i) {
            for (const double sign : {-1.0, 1.0}) {
                const double mu = 0.5 * (1.0 + sign * kNodes[i]);
                sum += fresnel(p, mu) * (kWeights[i] * mu);  // 2 mu times the half-interval 0.5
            }
        }
        return sum;
    }
    static double alphaOf(double roughness) {
        return std::max(TrowbridgeReitz::alphaFromRoughness(roughness), 0.0);
    }
    TrowbridgeReitz distribution(const ShadingPoint& p) const {
        // A rough material keeps alpha above the smooth limit where a
        // texture lowers it, so every point has a density.
        const double alpha = std::max(alphaOf(roughness_.at(p)), TrowbridgeReitz::kSmoothAlpha);
        return TrowbridgeReitz(alpha, alpha);
    }
    RGB fresnel(const ShadingPoint& p, double cosTheta) const {
        if (index_) return fresnelConductor(cosTheta, index_->eta, index_->k);
        // A normal-incidence reflectance r is the conductor with eta = 1 and
        // k = 2 sqrt(r / (1 - r)) (pbrt-v4's mapping).
        const RGB r = reflectance_.at(p).min(0.9999);
        const RGB k = 2.0 * (r / (1.0 - r)).sqrt();
        return fresnelConductor(cosTheta, RGB::Ones(), k);
    }

    std::optional<ComplexIndex> index_;
    ColorParameter reflectance_;
    ScalarParameter roughness_;
    bool smooth_ = true;
    const MicrofacetAlbedoTable* albedo_ = nullptr;  ///< with multiple scattering
    std::optional<RGB> fixedFresnelAverage_;
};

}  // namespace

Material readConductorMaterial(geometry::JsonObjectReader& r, const MaterialContext& context) {
    const int forms = int(r.has("metal")) + int(r.has("eta") || r.has("k")) + int(r.has("reflectance"));
    if (forms > 1) r.failHere("give one of \"metal\", \"eta\" and \"k\", or \"reflectance\"");
    std::optional<ComplexIndex> index;
    ColorParameter reflectance;
    if (r.has("reflectance")) {
        reflectance = readColorParameter(r, "reflectance", RGB::Ones(), context, 0.0, 1.0);
    } else if (r.has("eta") || r.has("k")) {
        if (!r.has("eta") || !r.has("k")) r.failHere("\"eta\" and \"k\" go together");
        index = ComplexIndex{readColor(r, "eta", RGB::Ones()), readColor(r, "k", RGB::Zero())};
        if (!(index->eta > 0).all()) r.fail("eta", "must be positive");
    } else {
        std::vector<std::string> names;
        for (const auto& [name, value] : metals()) names.push_back(name);
        index = metals().at(r.choice("metal", names, "aluminium"));
    }
    Material m;
    ScalarParameter roughness = readScalarParameter(r, "roughness", 0.0, context, 0.0, 1.0);
    m.bsdf = std::make_shared<ConductorBSDF>(index, std::move(reflectance), std::move(roughness),
                                             r.boolean("multiple_scattering", true));
    return m;
}

}  // namespace isotrace
