// "diffuse": Lambertian reflection, f = albedo / pi, sampled in proportion
// to the cosine so each sample's weight is the albedo itself.
#include <numbers>

#include "renderer/material.h"
#include "renderer/sampling/sampling.h"

namespace isotrace {

namespace {

class DiffuseBSDF final : public BSDF {
public:
    explicit DiffuseBSDF(ColorParameter albedo) : albedo_(std::move(albedo)) {}

    uint32_t flags() const override { return kBSDFDiffuseReflection; }

    RGB evaluate(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const override {
        if (!(p.shadingNormal.dot(wi) > 0)) return RGB::Zero();
        return albedo_.at(p) / std::numbers::pi;
    }
    double pdf(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const override {
        const double cosTheta = p.shadingNormal.dot(wi);
        return cosTheta > 0 ? cosTheta / std::numbers::pi : 0.0;
    }
    std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& wo, Sampler& sampler) const override {
        BSDFSample s;
        s.wi = sampleCosineHemisphere(p.shadingNormal, sampler.get2D());
        const double cosTheta = p.shadingNormal.dot(s.wi);
        if (!(cosTheta > 0)) return std::nullopt;
        s.weight = albedo_.at(p);
        s.pdf = cosTheta / std::numbers::pi;
        return s;
    }
    RGB albedo(const ShadingPoint& p) const override { return albedo_.at(p); }

private:
    ColorParameter albedo_;
};

}  // namespace

Material readDiffuseMaterial(geometry::JsonObjectReader& r, const MaterialContext& context) {
    Material m;
    m.bsdf = std::make_shared<DiffuseBSDF>(readColorParameter(r, "albedo", RGB::Constant(0.8), context, 0.0, 1.0));
    return m;
}

}  // namespace isotrace
