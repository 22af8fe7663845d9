// Path tracing with next-event estimation and multiple importance sampling.
#include <cmath>
#include <numbers>

#include "integrator.h"

namespace isotrace {

namespace {

class PathIntegrator final : public Integrator {
public:
    using Integrator::Integrator;

    RGB radiance(const Ray& cameraRay, Sampler& sampler) const override {
        const auto& lights = scene_.lights;
        const double lightCount = double(lights.size());
        const int maxDepth = scene_.integrator.maxDepth;
        RGB L = RGB::Zero(), beta = RGB::Ones();
        Ray ray = cameraRay;
        bool countEmissionFully = true;  // camera rays and specular bounces cannot sample lights
        double bsdfPdf = 0.0;
        Vec3 previous = ray.origin;

        for (int depth = 0;; ++depth) {
            SurfaceHit hit;
            if (!scene_.intersect(ray, INFINITY, hit)) {
                if (scene_.environmentLight >= 0) {
                    const Light& env = lights[scene_.environmentLight];
                    const double w = countEmissionFully ? 1.0 : powerHeuristic(bsdfPdf, env.pdf(previous, {}, {}) / lightCount);
                    L += beta * w * env.radiance();
                }
                break;
            }
            const SceneObject& object = scene_.objects[hit.object];
            const Material& material = scene_.materials[object.material];
            const Vec3 wo = -ray.direction;
            if (material.isEmissive()) {
                const bool front = material.twoSided || hit.geometricNormal.dot(wo) > 0;
                if (front) {
                    double w = 1.0;
                    if (!countEmissionFully && object.areaLight >= 0) {
                        const double lightPdf = lights[object.areaLight].pdf(previous, hit.position, hit.geometricNormal) / lightCount;
                        w = powerHeuristic(bsdfPdf, lightPdf);
                    }
                    L += beta * w * material.radiance;
                }
                break;  // emitters reflect nothing
            }
            if (depth >= maxDepth) break;

            // Shade with normals facing the incoming ray (two-sided surfaces).
            const Vec3 ng = hit.geometricNormal.dot(wo) >= 0 ? hit.geometricNormal : Vec3(-hit.geometricNormal);
            Vec3 ns = hit.shadingNormal;
            if (ns.dot(ng) < 0) ns = -ns;

            if (material.type == Material::Type::Mirror) {
                const Vec3 wi = reflect(ray.direction, ns);
                beta *= material.reflectance;
                ray = {offsetOrigin(hit.position, ng, wi), wi};
                countEmissionFully = true;
                previous = hit.position;
                continue;
            }

            // Diffuse: next-event estimation towards one light chosen uniformly.
            const RGB f = material.albedo / std::numbers::pi;
            const double uLight = sampler.get1D();
            const Eigen::Vector2d uSample = sampler.get2D();
            if (!lights.empty()) {
                const size_t index = std::min(size_t(uLight * lightCount), lights.size() - 1);
                const Light& light = lights[index];
                const LightSample ls = light.sample(hit.position, uSample);
                const double cosTheta = ns.dot(ls.direction);
                if (ls.pdf > 0 && cosTheta > 0 && ng.dot(ls.direction) > 0 && (ls.radiance > 0).any()) {
                    const Vec3 origin = offsetOrigin(hit.position, ng, ls.direction);
                    const double tMax = std::isfinite(ls.distance) ? ls.distance - 2.0 * rayOffset(hit.position) : INFINITY;
                    if (!scene_.occluded(origin, ls.direction, tMax)) {
                        const double lightPdf = ls.pdf / lightCount;
                        const double w = ls.isDelta ? 1.0 : powerHeuristic(lightPdf, cosTheta / std::numbers::pi);
                        L += beta * f * ls.radiance * (w * cosTheta / lightPdf);
                    }
                }
            }

            // Continue the path by sampling the cosine lobe: f cos / pdf = albedo.
            const Vec3 wi = sampleCosineHemisphere(ns, sampler.get2D());
            const double cosTheta = ns.dot(wi);
            if (!(cosTheta > 0) || ng.dot(wi) <= 0) break;
            beta *= material.albedo;
            bsdfPdf = cosTheta / std::numbers::pi;
            countEmissionFully = false;
            previous = hit.position;
            ray = {offsetOrigin(hit.position, ng, wi), wi};

            const double uRoulette = sampler.get1D();
            if (depth + 1 >= scene_.integrator.russianRouletteDepth) {
                const double survive = std::min(1.0, beta.maxCoeff());
                if (survive <= 0 || uRoulette >= survive) break;
                beta /= survive;
            }
        }
        return L;
    }
};

}  // namespace

std::unique_ptr<Integrator> makePathIntegrator(const Scene& scene) { return std::make_unique<PathIntegrator>(scene); }

}  // namespace isotrace
