#include "renderer/lights/implicit_emitter_light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "renderer/object_lights.h"
#include "renderer/sampling/sampling.h"

namespace isotrace {

namespace {

// cos of the half-angle of the cone of directions from a point at distance
// d to a sphere of radius r (d > r).
double coneCosine(double r, double d) { return std::sqrt(std::max(0.0, 1.0 - (r * r) / (d * d))); }

}  // namespace

ImplicitEmitterLight::ImplicitEmitterLight(const Scene& scene, const SceneObject& object, const Emission& emission)
    : shape_(scene.shapeScene(object)),
      worldFromObject_(object.worldFromObject),
      objectFromWorld_(object.worldFromObject.inverse()),
      normalFromObject_(object.normalFromObject),
      emission_(emission) {
    const geometry::Box3 local = scene.surfaces[object.shape]->bounds();
    if (local.isEmpty()) return;
    geometry::Box3 world;
    for (int k = 0; k < 8; ++k) world.extend((worldFromObject_ * local.corner(k).homogeneous()).head<3>());
    center_ = world.center();
    radius_ = world.halfDiagonal();
}

double ImplicitEmitterLight::directionPdf(const Vec3& p, const Vec3& wi) const {
    const Vec3 toCenter = center_ - p;
    const double d = toCenter.norm();
    if (d <= radius_) return 1.0 / (4.0 * std::numbers::pi);
    const double cosMax = coneCosine(radius_, d);
    if (toCenter.dot(wi) / d < cosMax) return 0.0;
    return 1.0 / (2.0 * std::numbers::pi * (1.0 - cosMax));
}

LightSample ImplicitEmitterLight::sample(const LightSampleContext& context, const Eigen::Vector2d& u) const {
    LightSample s;
    if (!(radius_ > 0)) return s;
    const Vec3& p = context.p;
    const Vec3 toCenter = center_ - p;
    const double d = toCenter.norm();
    if (d <= radius_) {
        s.direction = sampleUniformSphere(u);
    } else {
        const double phi = 2.0 * std::numbers::pi * u.y();
        const Vec3 w = toCenter / d;
        Vec3 a, b;
        orthonormalBasis(w, a, b);
        const double cosTheta = 1.0 - u.x() * (1.0 - coneCosine(radius_, d));
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        s.direction = (sinTheta * std::cos(phi) * a + sinTheta * std::sin(phi) * b + cosTheta * w).normalized();
    }
    s.pdf = directionPdf(p, s.direction);

    // The first point of the object along the direction, traced in the
    // object's space (an affine map keeps t).
    RTCIntersectContext rtcContext;
    rtcInitIntersectContext(&rtcContext);
    RTCRayHit rh = embreeRayHit((objectFromWorld_ * p.homogeneous()).head<3>(),
                                objectFromWorld_.topLeftCorner<3, 3>() * s.direction, INFINITY);
    rtcIntersect1(shape_, &rtcContext, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return s;  // a direction of the cone that misses: no light
    s.distance = rh.ray.tfar;
    s.point = p + s.distance * s.direction;
    const Vec3 n = (normalFromObject_ * Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)).normalized();
    s.radiance = emission_.emitted(n, -s.direction);
    return s;
}

double ImplicitEmitterLight::pdf(const LightSampleContext& context, const Vec3& wi, const Vec3&, const Vec3&) const {
    return radius_ > 0 ? directionPdf(context.p, wi) : 0.0;
}

int ImplicitEmitterLight::sideOfPlane(const Vec3& point, const Vec3& normal) const {
    const double h = normal.dot(center_ - point);
    if (!(radius_ > 0) || std::abs(h) <= radius_) return 0;
    return h > 0 ? 1 : -1;
}

double ImplicitEmitterLight::importance(const LightSampleContext& context) const {
    if (!(radius_ > 0)) return 0.0;
    // A uniformly emitting sphere of the bounding radius: pi L (r/d)^2 on a
    // surface facing it, pi L from inside.
    const Vec3 toCenter = center_ - context.p;
    const double d = toCenter.norm();
    const double solid = d <= radius_ ? 1.0 : (radius_ * radius_) / (d * d);
    const double cosReceiver =
        context.n.isZero() || d <= radius_ ? 1.0 : cosineBound(context.n, toCenter / d, sphereSinHalfAngle(radius_, d));
    return cosReceiver > 0 ? luminance(emission_.radiance) * std::numbers::pi * solid * cosReceiver : 0.0;
}

std::optional<LightBounds> ImplicitEmitterLight::bounds() const {
    if (!(radius_ > 0)) return std::nullopt;
    // As importance(): a sphere of the bounding radius, emitting every way.
    LightBounds b = pointSourceBounds(center_, luminance(emission_.radiance) * std::numbers::pi * radius_ * radius_);
    b.box = geometry::Box3::around(center_, radius_);
    return b;
}

std::unique_ptr<Light> makeImplicitEmitterLight(const Scene& scene, const SceneObject& object,
                                                const Emission& emission) {
    return std::make_unique<ImplicitEmitterLight>(scene, object, emission);
}

}  // namespace isotrace
