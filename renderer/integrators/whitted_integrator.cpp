// "whitted": the fast preview. Direct light with hard shadows, recursion
// through delta (mirror) lobes, and infinite lights as unshadowed ambient
// light.
#include <cmath>

#include "renderer/integrator.h"

namespace isotrace {

namespace {

class WhittedIntegrator final : public Integrator {
public:
    explicit WhittedIntegrator(int maxDepth) : maxDepth_(maxDepth) {}

    const char* typeName() const override { return "whitted"; }

    RGB radiance(const Scene& scene, const Ray& cameraRay, Sampler& sampler) const override {
        RGB L = RGB::Zero(), beta = RGB::Ones();
        Ray ray = cameraRay;
        for (int depth = 0;; ++depth) {
            SurfaceHit hit;
            if (!scene.intersect(ray, INFINITY, hit)) {
                if (scene.environmentLight >= 0)
                    L += beta * scene.lights[scene.environmentLight]->escapedRadiance(ray.direction);
                break;
            }
            const Material& material = scene.materials[scene.objects[hit.object].material];
            const Vec3 wo = -ray.direction;
            if (material.emission && (material.emission->twoSided || hit.geometricNormal.dot(wo) > 0))
                L += beta * material.emission->radiance;
            if (!material.bsdf) break;
            const BSDF& bsdf = *material.bsdf;
            const ShadingPoint sp = shadingPointOf(hit, wo);
            const Vec3& ng = sp.geometricNormal;
            const Vec3& ns = sp.shadingNormal;
            if (bsdf.isDeltaOnly()) {
                if (depth >= maxDepth_) break;
                const std::optional<BSDFSample> s = bsdf.sample(sp, wo, sampler);
                if (!s) break;
                beta *= s->weight;
                ray = {offsetOrigin(hit.position, ng, s->wi), s->wi};
                continue;
            }
            for (const auto& light : scene.lights) {
                if (light->isInfinite() && !light->isDelta()) {
                    L += beta * bsdf.albedo(sp) * light->meanRadiance();
                    continue;
                }
                const LightSample ls = light->sample({hit.position, ns}, sampler.get2D());
                const double cosTheta = ns.dot(ls.direction);
                if (!(ls.pdf > 0) || cosTheta <= 0 || ng.dot(ls.direction) <= 0) continue;
                if (unoccluded(scene, hit.position, ng, ls))
                    L += beta * bsdf.evaluate(sp, wo, ls.direction) * ls.radiance * (cosTheta / ls.pdf);
            }
            break;
        }
        return L;
    }

private:
    int maxDepth_;
};

}  // namespace

std::unique_ptr<Integrator> readWhittedIntegrator(geometry::JsonObjectReader& r) {
    const int maxDepth = static_cast<int>(r.integer("max_depth", 8, 1, 1000));
    r.integer("rr_depth", 3, 1, 1000);  // accepted for either integrator; the preview has no roulette
    return std::make_unique<WhittedIntegrator>(maxDepth);
}

}  // namespace isotrace
