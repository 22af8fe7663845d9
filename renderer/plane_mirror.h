// Flat mirrors of a scene: mesh objects that only reflect, in whose planes
// the scene's lights are imaged (lights/mirror_image_light.h).
#pragma once

#include <vector>

#include "renderer/ray.h"

namespace isotrace {

/// A plane in world space, and reflection through it.
struct MirrorPlane {
    Vec3 point = Vec3::Zero();    ///< on the plane
    Vec3 normal = Vec3(0, 1, 0);  ///< unit

    double signedDistance(const Vec3& p) const { return normal.dot(p - point); }
    Vec3 reflectPoint(const Vec3& p) const { return p - 2.0 * signedDistance(p) * normal; }
    Vec3 reflectVector(const Vec3& v) const { return v - 2.0 * normal.dot(v) * normal; }
};

/// A flat mesh object whose material only reflects, and only in a delta
/// lobe (a mirror, a smooth conductor): lights are imaged in its plane.
/// Either side reflects.
struct PlaneMirror {
    int object = -1;  ///< index into Scene::objects
    MirrorPlane plane;
    /// Index into Scene::lights of each light's image in this mirror, or -1
    /// (lights across the plane, the environment).
    std::vector<int> imageOfLight;
};

}  // namespace isotrace
