// "whitted": the fast preview. Direct light with hard shadows, recursion
// through every delta lobe (mirrors, the coat of plastic, both ways through
// glass), and infinite lights as unshadowed ambient light.
#include <cmath>

#include "renderer/integrator.h"

namespace isotrace {

namespace {

class WhittedIntegrator final : public Integrator {
public:
    explicit WhittedIntegrator(int maxDepth) : maxDepth_(maxDepth) {}

    const char* typeName() const override { return "whitted"; }

    RGB radiance(const Scene& scene, const Ray& cameraRay, Sampler& sampler) const override {
        return traced(scene, cameraRay, RGB::Ones(), 0, scene.cameraInteriors, sampler);
    }

private:
    // Radiance along `ray` times beta. Delta lobes split the ray (glass
    // follows both its reflection and its refraction, as Whitted did);
    // branches whose weight falls below 1e-3 are dropped (Hall's adaptive
    // depth control), so the recursion stays small.
    RGB traced(const Scene& scene, const Ray& ray, const RGB& beta, int depth, const InteriorStack& interiors,
               Sampler& sampler) const {
        RGB L = RGB::Zero();
        SurfaceHit hit;
        if (!nextSurface(scene, ray, interiors, hit)) {
            if (scene.environmentLight >= 0)
                L += beta * interiors.radianceScale() * scene.lights[scene.environmentLight]->escapedRadiance(ray.direction);
            return L;
        }
        const Material& material = scene.materials[scene.objects[hit.object].material];
        const Vec3 wo = -ray.direction;
        if (material.emission && (material.emission->twoSided || hit.geometricNormal.dot(wo) > 0))
            L += beta * material.emission->radiance;
        if (!material.bsdf) return L;
        const BSDF& bsdf = *material.bsdf;
        const ShadingPoint sp = shadingPointOf(scene, hit, wo, hit.t * pixelSpreadAngle(scene));
        const Vec3& ng = sp.geometricNormal;
        const Vec3& ns = sp.shadingNormal;

        BSDFSample lobes[2];
        const ShadingPoint deltaSp = depth < maxDepth_ ? deltaShadingPoint(bsdf, sp, wo) : sp;
        const int count = depth < maxDepth_ ? bsdf.deltaLobes(deltaSp, wo, lobes) : 0;
        for (int i = 0; i < count; ++i) {
            const RGB weight = beta * lobes[i].weight;
            if (weight.maxCoeff() < 1e-3 || ng.dot(lobes[i].wi) * deltaSp.shadingNormal.dot(lobes[i].wi) <= 0) continue;
            InteriorStack after = interiors;
            recordSide(scene, hit, sp, lobes[i].wi, after);
            L += traced(scene, {offsetOrigin(hit.position, ng, lobes[i].wi), lobes[i].wi}, weight, depth + 1, after,
                        sampler);
        }
        if (bsdf.isDeltaOnly()) return L;

        const LightSampleContext here{hit.position, bsdf.transmits() ? Vec3(Vec3::Zero()) : ns};
        for (const Light* light : scene.groupedLights) {
            if (light->isInfinite() && !light->isDelta()) {
                L += beta * bsdf.albedo(sp) * light->meanRadiance();
                continue;
            }
            // A delta light's sample ignores u: the draw is skipped, not made
            // (2% of the CSG Whitted frame's whole process), and later
            // dimensions stay what they would be.
            Eigen::Vector2d u(0.5, 0.5);
            if (light->isDelta()) sampler.skip2D();
            else u = sampler.get2D();
            const LightSample ls = light->sample(here, u);
            if (!(ls.pdf > 0) || ng.dot(ls.direction) * ns.dot(ls.direction) <= 0) continue;
            const RGB f = bsdf.evaluate(sp, wo, ls.direction);
            if ((f > 0).any()) L += beta * f * shadowRayWeight(scene, hit.position, ng, ls) * ls.radiance *
                                   (std::abs(ns.dot(ls.direction)) / ls.pdf);
        }
        return L;
    }

    int maxDepth_;
};

}  // namespace

std::unique_ptr<Integrator> readWhittedIntegrator(geometry::JsonObjectReader& r) {
    const int maxDepth = static_cast<int>(r.integer("max_depth", 8, 1, 1000));
    r.integer("rr_depth", 3, 1, 1000);  // accepted for either integrator; the preview has no roulette
    return std::make_unique<WhittedIntegrator>(maxDepth);
}

}  // namespace isotrace
