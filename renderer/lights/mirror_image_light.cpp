#include "renderer/lights/mirror_image_light.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "renderer/scene.h"

namespace isotrace {

MirrorImageLight::MirrorImageLight(const Light& light, const MirrorPlane& plane, int mirrorIndex, int side)
    : light_(light), plane_(plane), mirrorIndex_(mirrorIndex), side_(side) {}

LightSample MirrorImageLight::sample(const LightSampleContext& context, const Eigen::Vector2d& u) const {
    const double h = height(context.p);
    if (!(h > 0)) return {};
    const LightSample real = light_.sample(reflected(context), u);
    if (!(real.pdf > 0)) return {};
    // From the reflected point the sample's ray rises through the plane at
    // the mirror point, then goes on to the light.
    const double rise = side_ * plane_.normal.dot(real.direction);
    if (!(rise > 0)) return {};
    const double toMirror = h / rise;
    if (!(toMirror < real.distance)) return {};  // the light's point lies behind the plane
    LightSample s = real;
    s.direction = plane_.reflectVector(real.direction).normalized();
    if (std::isfinite(real.distance)) s.point = plane_.reflectPoint(real.point);
    s.mirror = mirrorIndex_;
    return s;
}

double MirrorImageLight::pdf(const LightSampleContext& context, const Vec3& wi, const Vec3& onLight,
                             const Vec3& lightNormal) const {
    if (!(height(context.p) > 0)) return 0.0;
    return light_.pdf(reflected(context), plane_.reflectVector(wi), onLight, lightNormal);
}

std::optional<LightBounds> MirrorImageLight::bounds() const {
    std::optional<LightBounds> b = light_.bounds();
    if (!b) return b;
    geometry::Box3 image;
    for (int i = 0; i < 8; ++i) image.extend(plane_.reflectPoint(b->box.corner(i)));
    b->box = image;
    b->axis = plane_.reflectVector(b->axis).normalized();
    return b;
}

double MirrorImageLight::importance(const LightSampleContext& context) const {
    return height(context.p) > 0 ? light_.importance(reflected(context)) : 0.0;
}

namespace {

// The plane of a mesh object that is flat and flat-shaded (vertex normals,
// if any, all along the plane's normal), in world space.
std::optional<MirrorPlane> planeOf(const TriangleMesh& mesh, const SceneObject& object) {
    if (mesh.triangleCount() == 0) return std::nullopt;
    std::vector<Vec3> world(mesh.vertexCount());
    geometry::Box3 box;
    for (uint32_t i = 0; i < mesh.vertexCount(); ++i) {
        world[i] = (object.worldFromObject * mesh.vertex(i).homogeneous()).head<3>();
        box.extend(world[i]);
    }
    // The normal of the largest triangle: the best conditioned.
    Vec3 best = Vec3::Zero();
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3& a = world[mesh.indices[3 * t]];
        const Vec3 n = (world[mesh.indices[3 * t + 1]] - a).cross(world[mesh.indices[3 * t + 2]] - a);
        if (n.squaredNorm() > best.squaredNorm()) best = n;
    }
    if (!(best.squaredNorm() > 0)) return std::nullopt;
    MirrorPlane plane{world[mesh.indices[0]], best.normalized()};
    // Within float rounding of the plane: Embree stores positions as floats.
    const double tolerance = 1e-6 * (1.0 + box.upper.cwiseAbs().maxCoeff() + box.lower.cwiseAbs().maxCoeff());
    for (const Vec3& p : world)
        if (std::abs(plane.signedDistance(p)) > tolerance) return std::nullopt;
    for (size_t i = 0; i < mesh.normals.size() / 3; ++i) {
        const Vec3 n = object.normalFromObject * mesh.normal(uint32_t(i));
        if (!(n.norm() > 0) || std::abs(n.normalized().dot(plane.normal)) < 1.0 - 1e-6) return std::nullopt;
    }
    return plane;
}

}  // namespace

void addMirrorImages(Scene& scene, size_t maxImages) {
    for (size_t o = 0; o < scene.objects.size(); ++o) {
        SceneObject& object = scene.objects[o];
        const Material& material = scene.materials[object.material];
        if (object.kind != SceneObject::Kind::Mesh || !material.bsdf ||
            material.bsdf->flags() != kBSDFSpecularReflection)
            continue;
        const std::optional<MirrorPlane> plane = planeOf(*scene.meshes[object.shape], object);
        if (!plane) continue;
        object.planeMirror = int(scene.planeMirrors.size());
        scene.planeMirrors.push_back({int(o), *plane, {}});
    }
    const size_t lightCount = scene.lights.size();  // images are not imaged again
    size_t images = 0, skipped = 0;
    for (size_t m = 0; m < scene.planeMirrors.size(); ++m) {
        PlaneMirror& mirror = scene.planeMirrors[m];
        mirror.imageOfLight.assign(lightCount, -1);
        for (size_t l = 0; l < lightCount; ++l) {
            const Light& light = *scene.lights[l];
            const int side = light.sideOfPlane(mirror.plane.point, mirror.plane.normal);
            if (side == 0) continue;
            if (images == maxImages) {
                ++skipped;
                continue;
            }
            mirror.imageOfLight[l] = int(scene.lights.size());
            scene.lights.push_back(std::make_unique<MirrorImageLight>(light, mirror.plane, int(m), side));
            ++images;
        }
    }
    if (skipped > 0)
        scene.warnings.push_back(std::to_string(skipped) + " images of lights in plane mirrors skipped past " +
                                 std::to_string(maxImages) +
                                 ": their light reaches the scene only through BSDF samples");
}

}  // namespace isotrace
