// What point and spot lights share: a delta light at one position, whose
// intensity towards the shading point the light decides.
#pragma once

#include "renderer/light.h"

namespace isotrace {

/// The sample of a point at `position` of intensity `intensity` towards the
/// context (radiance = intensity / d^2).
inline LightSample pointEmitterSample(const Vec3& position, const RGB& intensity, const LightSampleContext& context) {
    LightSample s;
    const Vec3 d = position - context.p;
    s.point = position;
    s.distance = d.norm();
    s.direction = d / s.distance;
    s.radiance = intensity / (s.distance * s.distance);
    s.pdf = 1.0;
    s.isDelta = true;
    return s;
}

/// Which side of the plane through `point` with unit `normal` a point light
/// at `position` lies on (Light::sideOfPlane).
inline int sideOfPlaneOfPoint(const Vec3& position, const Vec3& point, const Vec3& normal) {
    const double h = normal.dot(position - point);
    return h > 0 ? 1 : h < 0 ? -1 : 0;
}

}  // namespace isotrace
