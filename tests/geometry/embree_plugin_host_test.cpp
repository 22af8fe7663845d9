// A host that knows nothing of isotrace's renderer: it parses a field
// description, attaches it to its own Embree scene with bare Embree calls,
// and traces rays. This is the plugin API of docs/plugin-api.md.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/tracing/embree_implicit_geometry.h"
#include "geometry/description/field_parser.h"

using namespace isotrace::geometry;

TEST(EmbreePluginHost, TracesAFieldDescriptionWithBareEmbreeCalls) {
    const Json fields = Json::parse(R"({
        "ball": {"type": "sphere", "radius": 1},
        "hole": {"type": "cylinder", "radius": 0.3, "height": 4},
        "drilled": {"type": "difference", "of": ["ball", {"type": "transform", "rotate": {"axis": [1, 0, 0], "angle": 90}, "of": "hole"}]}
    })");
    FieldLibrary library(fields, "/fields", "host.json");
    ImplicitSurface surface(library.compile("drilled"));

    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    const unsigned geomID = attachImplicitSurface(device, scene, surface);
    rtcCommitScene(scene);

    auto trace = [&](float ox, float oy, float oz, float dx, float dy, float dz) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh{};
        rh.ray.org_x = ox, rh.ray.org_y = oy, rh.ray.org_z = oz;
        rh.ray.dir_x = dx, rh.ray.dir_y = dy, rh.ray.dir_z = dz;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = INFINITY;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        return rh;
    };
    // Off the hole: the sphere at distance 2.
    RTCRayHit a = trace(0.6, 0, -3, 0, 0, 1);
    ASSERT_EQ(a.hit.geomID, geomID);
    EXPECT_NEAR(a.ray.tfar, 3.0 - std::sqrt(1.0 - 0.36), 1e-5);
    // Down the hole (along z after the rotation): nothing to hit.
    RTCRayHit b = trace(0, 0, -3, 0, 0, 1);
    EXPECT_EQ(b.hit.geomID, RTC_INVALID_GEOMETRY_ID);
    // The shading calls a host needs: field value and normal at the hit.
    const Vec3 p = Vec3(0.6, 0, -3) + double(a.ray.tfar) * Vec3(0, 0, 1);
    EXPECT_NEAR(surface.field().value(p), 0.0, 1e-5);
    EXPECT_LT((surface.normal(p) - p.normalized()).norm(), 1e-3);

    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}
