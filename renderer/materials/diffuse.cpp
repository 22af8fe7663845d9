// "diffuse": Lambertian reflection, f = albedo / pi, sampled in proportion
// to the cosine so each sample's weight is the albedo itself.
#include <numbers>

#include "renderer/material.h"
#include "renderer/sampling.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class DiffuseBSDF final : public BSDF {
public:
    explicit DiffuseBSDF(const RGB& albedo) : albedo_(albedo) {}

    uint32_t flags() const override { return kBSDFDiffuseReflection; }

    RGB evaluate(const ShadingPoint& p, const Vec3& wo, const Vec3& wi) const override {
        return albedo_ / std::numbers::pi;
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
        s.weight = albedo_;
        s.pdf = cosTheta / std::numbers::pi;
        return s;
    }
    RGB albedo(const ShadingPoint&) const override { return albedo_; }

private:
    RGB albedo_;
};

}  // namespace

Material readDiffuseMaterial(geometry::JsonObjectReader& r) {
    Material m;
    const RGB albedo = readColor(r, "albedo", RGB::Constant(0.8));
    if ((albedo > 1.0).any()) r.fail("albedo", "albedo above 1 creates energy");
    m.bsdf = std::make_shared<DiffuseBSDF>(albedo);
    return m;
}

}  // namespace isotrace
