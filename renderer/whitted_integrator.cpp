// Whitted-style preview: direct light with hard shadows, mirror recursion,
// and the environment as unshadowed ambient light on diffuse surfaces.
#include <cmath>
#include <numbers>

#include "integrator.h"

namespace isotrace {

namespace {

class WhittedIntegrator final : public Integrator {
public:
    using Integrator::Integrator;

    RGB radiance(const Ray& cameraRay, Sampler& sampler) const override {
        RGB L = RGB::Zero(), beta = RGB::Ones();
        Ray ray = cameraRay;
        for (int depth = 0;; ++depth) {
            SurfaceHit hit;
            if (!scene_.intersect(ray, INFINITY, hit)) {
                if (scene_.environmentLight >= 0) L += beta * scene_.lights[scene_.environmentLight].radiance();
                break;
            }
            const SceneObject& object = scene_.objects[hit.object];
            const Material& material = scene_.materials[object.material];
            const Vec3 wo = -ray.direction;
            if (material.isEmissive()) {
                if (material.twoSided || hit.geometricNormal.dot(wo) > 0) L += beta * material.radiance;
                break;
            }
            const Vec3 ng = hit.geometricNormal.dot(wo) >= 0 ? hit.geometricNormal : Vec3(-hit.geometricNormal);
            Vec3 ns = hit.shadingNormal;
            if (ns.dot(ng) < 0) ns = -ns;
            if (material.type == Material::Type::Mirror) {
                if (depth >= scene_.integrator.maxDepth) break;
                const Vec3 wi = reflect(ray.direction, ns);
                beta *= material.reflectance;
                ray = {offsetOrigin(hit.position, ng, wi), wi};
                continue;
            }
            const RGB f = material.albedo / std::numbers::pi;
            for (const Light& light : scene_.lights) {
                if (light.type() == Light::Type::Environment) {
                    L += beta * material.albedo * light.radiance();
                    continue;
                }
                const LightSample ls = light.sample(hit.position, sampler.get2D());
                const double cosTheta = ns.dot(ls.direction);
                if (!(ls.pdf > 0) || cosTheta <= 0 || ng.dot(ls.direction) <= 0) continue;
                const Vec3 origin = offsetOrigin(hit.position, ng, ls.direction);
                const double tMax = std::isfinite(ls.distance) ? ls.distance - 2.0 * rayOffset(hit.position) : INFINITY;
                if (!scene_.occluded(origin, ls.direction, tMax)) L += beta * f * ls.radiance * (cosTheta / ls.pdf);
            }
            break;
        }
        return L;
    }
};

}  // namespace

std::unique_ptr<Integrator> makeWhittedIntegrator(const Scene& scene) {
    return std::make_unique<WhittedIntegrator>(scene);
}

}  // namespace isotrace
