#include "renderer/integrator.h"

#include <cmath>

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

ShadingPoint shadingPointOf(const SurfaceHit& hit, const Vec3& wo) {
    ShadingPoint p;
    p.position = hit.position;
    p.geometricNormal = hit.geometricNormal.dot(wo) >= 0 ? hit.geometricNormal : Vec3(-hit.geometricNormal);
    p.shadingNormal = hit.shadingNormal;
    if (p.shadingNormal.dot(p.geometricNormal) < 0) p.shadingNormal = -p.shadingNormal;
    return p;
}

}  // namespace isotrace
