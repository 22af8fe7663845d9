// "mirror": perfect specular reflection about the shading normal, scaled by
// a reflectance; a single delta lobe.
#include "renderer/material.h"
#include "renderer/sampling.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class MirrorBSDF final : public BSDF {
public:
    explicit MirrorBSDF(const RGB& reflectance) : reflectance_(reflectance) {}

    uint32_t flags() const override { return kBSDFSpecularReflection; }
    RGB evaluate(const ShadingPoint&, const Vec3&, const Vec3&) const override { return RGB::Zero(); }
    double pdf(const ShadingPoint&, const Vec3&, const Vec3&) const override { return 0.0; }
    std::optional<BSDFSample> sample(const ShadingPoint& p, const Vec3& wo, Sampler&) const override {
        BSDFSample s;
        s.wi = reflect(-wo, p.shadingNormal);
        s.weight = reflectance_;
        s.delta = true;
        return s;
    }
    RGB albedo(const ShadingPoint&) const override { return reflectance_; }

private:
    RGB reflectance_;
};

}  // namespace

Material readMirrorMaterial(geometry::JsonObjectReader& r) {
    Material m;
    const RGB reflectance = readColor(r, "reflectance", RGB::Constant(1.0));
    if ((reflectance > 1.0).any()) r.fail("reflectance", "reflectance above 1 creates energy");
    m.bsdf = std::make_shared<MirrorBSDF>(reflectance);
    return m;
}

}  // namespace isotrace
