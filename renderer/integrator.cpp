#include "renderer/integrator.h"

#include <cmath>
#include <numbers>

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
    if (hit.object >= 0) p.footprint = footprint * scene.objects[hit.object].objectFromWorldScale;
    return p;
}

double pixelSpreadAngle(const Scene& scene) {
    const double fov = scene.camera.verticalFovDegrees * std::numbers::pi / 180.0;
    return 2.0 * std::tan(0.5 * fov) / std::max(1, scene.film.height);
}

}  // namespace isotrace
