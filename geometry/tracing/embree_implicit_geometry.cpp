#include "geometry/tracing/embree_implicit_geometry.h"

#include <cassert>
#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {

void boundsCallback(const RTCBoundsFunctionArguments* args) {
    const auto* surface = static_cast<const ImplicitSurface*>(args->geometryUserPtr);
    const Box3& box = surface->cells()[args->primID].box;
    // Round outward so float bounds contain the double-precision cell.
    args->bounds_o->lower_x = std::nextafter(float(box.lower.x()), -INFINITY);
    args->bounds_o->lower_y = std::nextafter(float(box.lower.y()), -INFINITY);
    args->bounds_o->lower_z = std::nextafter(float(box.lower.z()), -INFINITY);
    args->bounds_o->upper_x = std::nextafter(float(box.upper.x()), INFINITY);
    args->bounds_o->upper_y = std::nextafter(float(box.upper.y()), INFINITY);
    args->bounds_o->upper_z = std::nextafter(float(box.upper.z()), INFINITY);
}

// Marches one cell for a hit in (tnear, tfar): the nearest, or for an
// occlusion query any.
TraceResult marchCell(const RTCRay& ray, const ImplicitSurface& surface, unsigned primID, bool anyHit) {
    if ((ray.mask & surface.rayMask()) == 0) return {};
    const Vec3 origin(ray.org_x, ray.org_y, ray.org_z);
    const Vec3 direction(ray.dir_x, ray.dir_y, ray.dir_z);
    return surface.intersectCell(primID, origin, direction, ray.tnear, ray.tfar, anyHit);
}

// The candidate hit at t: object-space normal = field gradient, ids, and
// the instance ids, which Embree leaves to user geometry under instances.
// Intersect and occluded arguments carry the same fields.
template <class Arguments>
RTCHit candidateHit(const RTCRay& ray, const ImplicitSurface& surface, const Arguments* args, const TraceResult& r) {
    RTCHit hit{};
    Vec3 g = r.gradient;
    if (!r.gradientKnown) {
        const Vec3 p = Vec3(ray.org_x, ray.org_y, ray.org_z) + r.t * Vec3(ray.dir_x, ray.dir_y, ray.dir_z);
        surface.cellProgram(surface.cells()[args->primID]).valueAndGradient(p, g);
    }
    hit.Ng_x = float(g.x());
    hit.Ng_y = float(g.y());
    hit.Ng_z = float(g.z());
    hit.primID = args->primID;
    hit.geomID = args->geomID;
    for (unsigned level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; ++level)
        hit.instID[level] = args->context->instID[level];
    return hit;
}

// Offers a candidate to the filter functions with tfar set to its t, as
// Embree does for its own primitives; true when accepted. On rejection the
// ray's tfar is restored.
template <class Arguments, class FilterCall>
bool offerToFilters(const Arguments* args, RTCRay& ray, RTCHit& candidate, double t, FilterCall filter) {
    const float oldTfar = ray.tfar;
    ray.tfar = float(t);
    int valid = -1;
    RTCFilterFunctionNArguments filterArgs;
    filterArgs.valid = &valid;
    filterArgs.geometryUserPtr = args->geometryUserPtr;
    filterArgs.context = args->context;
    filterArgs.ray = reinterpret_cast<RTCRayN*>(&ray);
    filterArgs.hit = reinterpret_cast<RTCHitN*>(&candidate);
    filterArgs.N = 1;
    filter(args, &filterArgs);
    if (valid != -1) ray.tfar = oldTfar;
    return valid == -1;
}

void intersectCallback(const RTCIntersectFunctionNArguments* args) {
    assert(args->N == 1);
    if (!args->valid[0]) return;
    const auto& surface = *static_cast<const ImplicitSurface*>(args->geometryUserPtr);
    RTCRayHit* rayhit = reinterpret_cast<RTCRayHit*>(args->rayhit);
    const TraceResult r = marchCell(rayhit->ray, surface, args->primID, false);
    if (!r.hit) return;
    RTCHit candidate = candidateHit(rayhit->ray, surface, args, r);
    if (offerToFilters(args, rayhit->ray, candidate, r.t, rtcFilterIntersection)) rayhit->hit = candidate;
}

void occludedCallback(const RTCOccludedFunctionNArguments* args) {
    assert(args->N == 1);
    if (!args->valid[0]) return;
    const auto& surface = *static_cast<const ImplicitSurface*>(args->geometryUserPtr);
    RTCRay* ray = reinterpret_cast<RTCRay*>(args->ray);
    const TraceResult r = marchCell(*ray, surface, args->primID, true);
    if (!r.hit) return;
    RTCHit candidate = candidateHit(*ray, surface, args, r);
    // An accepted occluder ends traversal: Embree reads tfar = -inf as "hit".
    if (offerToFilters(args, *ray, candidate, r.t, rtcFilterOcclusion)) ray->tfar = -std::numeric_limits<float>::infinity();
}

RTCGeometry newImplicitGeometry(RTCDevice device, ImplicitSurface& surface) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(surface.cells().size()));
    rtcSetGeometryUserData(geometry, &surface);
    rtcSetGeometryBoundsFunction(geometry, boundsCallback, nullptr);
    rtcSetGeometryIntersectFunction(geometry, intersectCallback);
    rtcSetGeometryOccludedFunction(geometry, occludedCallback);
    rtcSetGeometryMask(geometry, surface.rayMask());
    rtcCommitGeometry(geometry);
    return geometry;
}

}  // namespace

unsigned attachImplicitSurface(RTCDevice device, RTCScene scene, ImplicitSurface& surface, unsigned mask) {
    surface.setRayMask(mask);
    RTCGeometry geometry = newImplicitGeometry(device, surface);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    return id;
}

void attachImplicitSurfaceAs(RTCDevice device, RTCScene scene, ImplicitSurface& surface, unsigned id) {
    RTCGeometry geometry = newImplicitGeometry(device, surface);
    rtcAttachGeometryByID(scene, geometry, id);
    rtcReleaseGeometry(geometry);
}

}  // namespace isotrace::geometry
