// "mirror": perfect specular reflection about the shading normal, scaled by
// a reflectance; a single delta lobe.
#include "renderer/material.h"
#include "renderer/sampling/sampling.h"

namespace isotrace {

namespace {

class MirrorBSDF final : public BSDF {
public:
    explicit MirrorBSDF(ColorParameter reflectance) : reflectance_(std::move(reflectance)) {}

    uint32_t flags() const override { return kBSDFSpecularReflection; }
    RGB evaluate(const ShadingPoint&, const Vec3&, const Vec3&) const override { return RGB::Zero(); }
    double pdf(const ShadingPoint&, const Vec3&, const Vec3&) const override { return 0.0; }
    std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& wo, Sampler&) const override {
        BSDFSample lobes[2];
        deltaLobes(p, wo, lobes);
        return lobes[0];
    }
    int deltaLobes(const ShadingPoint& p, const Vec3& wo, BSDFSample lobes[2]) const override {
        lobes[0].wi = reflect(-wo, p.shadingNormal);
        lobes[0].weight = reflectance_.at(p);
        lobes[0].delta = true;
        return 1;
    }
    RGB albedo(const ShadingPoint& p) const override { return reflectance_.at(p); }

private:
    ColorParameter reflectance_;
};

}  // namespace

Material readMirrorMaterial(geometry::JsonObjectReader& r, const MaterialContext& context) {
    Material m;
    m.bsdf = std::make_shared<MirrorBSDF>(readColorParameter(r, "reflectance", RGB::Constant(1.0), context, 0.0, 1.0));
    return m;
}

}  // namespace isotrace
