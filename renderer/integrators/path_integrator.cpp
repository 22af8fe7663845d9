// "path": unidirectional path tracing with next-event estimation, multiple
// importance sampling (power heuristic) and Russian roulette.
#include <cmath>

#include "renderer/integrator.h"

namespace isotrace {

namespace {

// A direction lies on the same side of the geometric and the shading
// surface: otherwise shading normals would leak light through the surface.
bool sameSide(const Vec3& ng, const Vec3& ns, const Vec3& w) { return ng.dot(w) * ns.dot(w) > 0; }

class PathIntegrator final : public Integrator {
public:
    PathIntegrator(int maxDepth, int russianRouletteDepth, LightSampling lightSampling)
        : maxDepth_(maxDepth), russianRouletteDepth_(russianRouletteDepth), lightSampling_(lightSampling) {}

    const char* typeName() const override { return "path"; }
    LightSampling lightSampling() const override { return lightSampling_; }

    RGB radiance(const Scene& scene, const Ray& cameraRay, Sampler& sampler) const override {
        const auto& lights = scene.lights;
        RGB L = RGB::Zero(), beta = RGB::Ones();
        Ray ray = cameraRay;
        bool countEmissionFully = true;  // camera rays and specular bounces cannot sample lights
        double bsdfPdf = 0.0;
        // The last non-delta vertex, where lights were last sampled.
        LightSampleContext previous{ray.origin, Vec3::Zero()};
        double previousImportance = 0.0;  // the lights' total importance there
        // A plane mirror the path bounced off straight after `previous`:
        // lights met next were also sampled there, as their images.
        int viaMirror = -1;
        Vec3 directionAtPrevious = Vec3::Zero();
        // Radiance scaling by refraction (1 / eta^2 per crossing), which
        // Russian roulette must not mistake for a loss or gain of energy.
        double etaScale = 1.0;
        // Distance travelled, for the pixel footprint textures filter over.
        double pathLength = 0.0;
        const double spread = pixelSpreadAngle(scene);
        InteriorStack interiors = scene.cameraInteriors;

        for (int depth = 0;; ++depth) {
            SurfaceHit hit;
            if (!nextSurface(scene, ray, interiors, hit)) {
                if (scene.environmentLight >= 0) {
                    const Light& env = *lights[scene.environmentLight];
                    const double lightPdf = env.pdf(previous, ray.direction, {}, {}) * scene.lightSampler.pmf(previous, scene.environmentLight, previousImportance);
                    const double w = countEmissionFully ? 1.0 : powerHeuristic(bsdfPdf, lightPdf);
                    L += beta * (w * interiors.radianceScale()) * env.escapedRadiance(ray.direction);
                }
                break;
            }
            pathLength += hit.t;
            const SceneObject& object = scene.objects[hit.object];
            const Material& material = scene.materials[object.material];
            const Vec3 wo = -ray.direction;
            if (material.emission) {
                const bool front = material.emission->twoSided || hit.geometricNormal.dot(wo) > 0;
                if (front) {
                    double w = 1.0;
                    const int light = object.lightAt(hit.primitive);
                    if (!countEmissionFully && light >= 0) {
                        const double lightPdf =
                            lights[light]->pdf(previous, ray.direction, hit.position, hit.geometricNormal) *
                            scene.lightSampler.pmf(previous, light, previousImportance);
                        w = powerHeuristic(bsdfPdf, lightPdf);
                    } else if (viaMirror >= 0 && light >= 0) {
                        if (const int image = scene.planeMirrors[viaMirror].imageOfLight[light]; image >= 0) {
                            const double imagePdf = lights[image]->pdf(previous, directionAtPrevious, hit.position,
                                                                       hit.geometricNormal) *
                                                    scene.lightSampler.pmf(previous, image, previousImportance);
                            w = powerHeuristic(bsdfPdf, imagePdf);
                        }
                    }
                    L += beta * w * material.emission->radiance;
                }
            }
            if (!material.bsdf) break;  // pure emitters reflect nothing
            if (depth >= maxDepth_) break;

            const BSDF& bsdf = *material.bsdf;
            const ShadingPoint sp = shadingPointOf(scene, hit, wo, pathLength * spread);
            const Vec3& ng = sp.geometricNormal;
            const Vec3& ns = sp.shadingNormal;

            if (bsdf.isDeltaOnly()) {
                const ShadingPoint deltaSp = deltaShadingPoint(bsdf, sp, wo);
                const std::optional<BSDFSample> s = bsdf.sample(deltaSp, wo, sampler);
                if (!s || !sameSide(ng, deltaSp.shadingNormal, s->wi)) break;
                recordSide(scene, hit, sp, s->wi, interiors);
                viaMirror = countEmissionFully ? -1 : object.planeMirror;
                directionAtPrevious = ray.direction;
                beta *= s->weight;
                etaScale *= s->etaRatio * s->etaRatio;
                ray = {offsetOrigin(hit.position, ng, s->wi), s->wi};
                countEmissionFully = true;
                continue;
            }

            // Next-event estimation towards one light chosen by its importance
            // here. A surface that transmits sees lights on both sides: its
            // context has no normal to bound them by.
            const double uLight = sampler.get1D();
            const Eigen::Vector2d uSample = sampler.get2D();
            const LightSampleContext here{hit.position, bsdf.transmits() ? Vec3(Vec3::Zero()) : ns};
            const double importance = scene.lightSampler.totalImportance(here);
            double lightChoice = 0.0;
            if (const int index = scene.lightSampler.sample(here, uLight, importance, lightChoice); index >= 0) {
                const Light& light = *lights[index];
                const LightSample ls = light.sample(here, uSample);
                if (ls.pdf > 0 && sameSide(ng, ns, ls.direction) && (ls.radiance > 0).any()) {
                    const RGB f = bsdf.evaluate(sp, wo, ls.direction);
                    const RGB through = (f > 0).any() ? shadowRayWeight(scene, hit.position, ng, ls) : RGB::Zero();
                    if ((through > 0).any()) {
                        const double lightPdf = ls.pdf * lightChoice;
                        const double w = ls.isDelta ? 1.0 : powerHeuristic(lightPdf, bsdf.pdf(sp, wo, ls.direction));
                        L += beta * f * through * ls.radiance * (w * std::abs(ns.dot(ls.direction)) / lightPdf);
                    }
                }
            }

            // Continue the path by sampling the BSDF.
            const std::optional<BSDFSample> s = bsdf.sample(sp, wo, sampler);
            if (!s || !sameSide(ng, ns, s->wi)) break;
            recordSide(scene, hit, sp, s->wi, interiors);
            beta *= s->weight;
            etaScale *= s->etaRatio * s->etaRatio;
            bsdfPdf = s->pdf;
            countEmissionFully = s->delta;
            viaMirror = -1;
            previous = here;
            previousImportance = importance;
            ray = {offsetOrigin(hit.position, ng, s->wi), s->wi};

            const double uRoulette = sampler.get1D();
            if (depth + 1 >= russianRouletteDepth_) {
                const double survive = std::min(1.0, beta.maxCoeff() * etaScale);
                if (survive <= 0 || uRoulette >= survive) break;
                beta /= survive;
            }
        }
        return L;
    }

private:
    int maxDepth_;
    int russianRouletteDepth_;
    LightSampling lightSampling_;
};

}  // namespace

std::unique_ptr<Integrator> makePathIntegrator(int maxDepth, int russianRouletteDepth, LightSampling lightSampling) {
    return std::make_unique<PathIntegrator>(maxDepth, russianRouletteDepth, lightSampling);
}

std::unique_ptr<Integrator> readPathIntegrator(geometry::JsonObjectReader& r) {
    const int maxDepth = static_cast<int>(r.integer("max_depth", 8, 1, 100000));
    const int rrDepth = static_cast<int>(r.integer("rr_depth", 3, 1, 100000));
    LightSampling lightSampling = LightSampling::Tree;
    lightSamplingNamed(r.choice("light_sampler", {"tree", "exhaustive"}, "tree"), lightSampling);
    return makePathIntegrator(maxDepth, rrDepth, lightSampling);
}

}  // namespace isotrace
