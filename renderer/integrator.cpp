#include "renderer/integrator.h"

namespace isotrace {

ShadingPoint shadingPointOf(const SurfaceHit& hit, const Vec3& wo) {
    ShadingPoint p;
    p.position = hit.position;
    p.geometricNormal = hit.geometricNormal.dot(wo) >= 0 ? hit.geometricNormal : Vec3(-hit.geometricNormal);
    p.shadingNormal = hit.shadingNormal;
    if (p.shadingNormal.dot(p.geometricNormal) < 0) p.shadingNormal = -p.shadingNormal;
    return p;
}

}  // namespace isotrace
