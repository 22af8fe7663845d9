#include "renderer/integrator.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace isotrace {

bool unoccluded(const Scene& scene, const Vec3& p, const Vec3& ng, const LightSample& sample) {
    const Vec3 origin = offsetOrigin(p, ng, sample.direction);
    if (!std::isfinite(sample.distance)) return !scene.occluded(origin, sample.direction, INFINITY);
    const Vec3 toLight = sample.point - origin;
    const double distance = toLight.norm();
    const double end = distance - 2.0 * rayOffset(sample.point);
    if (!(end > 0)) return true;  // the light touches the surface: nothing fits between
    return !scene.occluded(origin, toLight / distance, end);
}

RGB shadowRayWeight(const Scene& scene, const Vec3& p, const Vec3& ng, const LightSample& sample) {
    if (sample.mirror < 0) return unoccluded(scene, p, ng, sample) ? RGB::Ones() : RGB::Zero();
    const PlaneMirror& mirror = scene.planeMirrors[sample.mirror];
    // The mirror is flat: a ray that meets the mirror object at all meets it
    // where it crosses the plane, the point the sample was made through.
    SurfaceHit hit;
    const Ray toMirror{offsetOrigin(p, ng, sample.direction), sample.direction};
    const double toPlane = -mirror.plane.signedDistance(toMirror.origin) / mirror.plane.normal.dot(sample.direction);
    if (!(toPlane > 0)) return RGB::Zero();
    const double reach = toPlane + 4.0 * rayOffset(toMirror.origin + toPlane * sample.direction);
    if (!scene.intersect(toMirror, reach, hit) || hit.object != mirror.object) return RGB::Zero();
    const Vec3 wo = -sample.direction;
    const ShadingPoint sp = shadingPointOf(scene, hit, wo);
    BSDFSample lobes[2];
    const int count = scene.materials[scene.objects[hit.object].material].bsdf->deltaLobes(sp, wo, lobes);
    if (count < 1) return RGB::Zero();
    // The second leg, from the mirror point to the light's real point.
    LightSample beyond = sample;
    beyond.direction = mirror.plane.reflectVector(sample.direction);
    if (std::isfinite(sample.distance)) beyond.point = mirror.plane.reflectPoint(sample.point);
    return unoccluded(scene, hit.position, hit.geometricNormal, beyond) ? RGB(lobes[0].weight) : RGB::Zero();
}

ShadingPoint shadingPointOf(const Scene& scene, const SurfaceHit& hit, const Vec3& wo, double footprint) {
    ShadingPoint p;
    p.position = hit.position;
    p.outside = hit.geometricNormal.dot(wo) >= 0;
    p.geometricNormal = p.outside ? hit.geometricNormal : Vec3(-hit.geometricNormal);
    p.shadingNormal = hit.shadingNormal;
    if (p.shadingNormal.dot(p.geometricNormal) < 0) p.shadingNormal = -p.shadingNormal;
    p.objectPosition = hit.objectPosition;
    p.objectNormal = hit.objectNormal;
    p.uv = hit.uv;
    p.hasUv = hit.hasUv;
    if (hit.object >= 0) p.footprint = footprint * scene.objects[hit.object].objectFromWorldScale;
    p.uvFootprint = p.footprint * hit.uvPerLength;
    return p;
}

ShadingPoint deltaShadingPoint(const BSDF& bsdf, const ShadingPoint& sp, const Vec3& wo) {
    // Implicit surfaces and flat faces shade with their own normal: nothing
    // to check, and no lobes to find twice.
    if (sp.shadingNormal == sp.geometricNormal) return sp;
    ShadingPoint flat = sp;
    flat.shadingNormal = sp.geometricNormal;
    if (!(sp.shadingNormal.dot(wo) > 0)) return flat;
    BSDFSample lobes[2];
    const int count = bsdf.deltaLobes(sp, wo, lobes);
    for (int i = 0; i < count; ++i)
        if (sp.geometricNormal.dot(lobes[i].wi) * sp.shadingNormal.dot(lobes[i].wi) <= 0) return flat;
    return sp;
}

namespace {

/// The index of the solid an object's surface bounds, or 0.
double solidIndexOf(const Scene& scene, int object) {
    const BSDF* bsdf = scene.materials[scene.objects[object].material].bsdf.get();
    return bsdf ? bsdf->solidIndex() : 0.0;
}

/// A hit on a solid's surface whose side (as shadingPointOf judges it)
/// disagrees with what the path knows.
bool contradicts(const Scene& scene, const SurfaceHit& hit, const Vec3& direction, const InteriorStack& interiors) {
    if (!(solidIndexOf(scene, hit.object) > 0)) return false;
    const InteriorStack::Side side = interiors.side(hit.object);
    if (side == InteriorStack::Side::Unknown) return false;
    const bool entering = hit.geometricNormal.dot(direction) <= 0;
    return entering == (side == InteriorStack::Side::Inside);
}

}  // namespace

bool nextSurface(const Scene& scene, const Ray& ray, const InteriorStack& interiors, SurfaceHit& hit) {
    // A bound on passes, for a path whose record is wrong after all.
    constexpr int kMostPasses = 8;
    Ray r = ray;
    for (int pass = 0;; ++pass) {
        if (!scene.intersect(r, INFINITY, hit)) return false;
        if (pass == kMostPasses || !contradicts(scene, hit, r.direction, interiors)) {
            hit.t = (hit.position - ray.origin).norm();
            return true;
        }
        r.origin = hit.position + rayOffset(hit.position) * r.direction;
    }
}

void recordSide(const Scene& scene, const SurfaceHit& hit, const ShadingPoint& sp, const Vec3& wi,
                InteriorStack& interiors) {
    const double ior = solidIndexOf(scene, hit.object);
    if (!(ior > 0)) return;
    const bool crossed = sp.geometricNormal.dot(wi) < 0;
    interiors.record(hit.object, ior, sp.outside == crossed);
}

InteriorStack interiorsAt(const Scene& scene, const Vec3& point) {
    // Along one ray from the point, the first surface of each closed solid
    // seen from inside is one the point is in; solids the ray never meets
    // it is outside of. The direction avoids the axes and diagonals that
    // scenes are built along.
    const Vec3 direction = Vec3(0.2672, 0.5345, 0.8018).normalized();
    InteriorStack interiors;
    std::vector<bool> met(scene.objects.size(), false);
    Ray ray{point, direction};
    SurfaceHit hit;
    for (int crossings = 0; crossings < 10000 && scene.intersect(ray, INFINITY, hit); ++crossings) {
        const double ior = solidIndexOf(scene, hit.object);
        if (ior > 0 && !met[size_t(hit.object)]) {
            met[size_t(hit.object)] = true;
            if (hit.geometricNormal.dot(direction) > 0) interiors.record(hit.object, ior, true);
        }
        ray.origin = hit.position + rayOffset(hit.position) * direction;
    }
    return interiors;
}

double pixelSpreadAngle(const Scene& scene) {
    const double fov = scene.camera.verticalFovDegrees * std::numbers::pi / 180.0;
    return 2.0 * std::tan(0.5 * fov) / std::max(1, scene.film.height);
}

}  // namespace isotrace
