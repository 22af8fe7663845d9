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
