// Traces one ray through a field attached with the installed library.
#include <embree3/rtcore.h>

#include <cmath>
#include <cstdio>

#include "geometry/tracing/embree_implicit_geometry.h"
#include "geometry/description/field_parser.h"

int main() {
    using namespace isotrace::geometry;
    FieldLibrary library(Json::parse(R"({"ball": {"type": "sphere", "radius": 1}})"), "/fields", "consumer");
    ImplicitSurface surface(library.compile("ball"));
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    attachImplicitSurface(device, scene, surface);
    rtcCommitScene(scene);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_z = -3.0f;
    rh.ray.dir_z = 1.0f;
    rh.ray.tfar = INFINITY;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    const bool ok = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && std::abs(rh.ray.tfar - 2.0f) < 1e-5f;
    std::printf("hit at t = %g: %s\n", rh.ray.tfar, ok ? "ok" : "wrong");
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return ok ? 0 : 1;
}
