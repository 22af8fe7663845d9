#include "geometry/tracing/embree_implicit_geometry.h"

#include <gtest/gtest.h>

#include "geometry/description/field_parser.h"
#include "support/compile_field.h"
#include "support/embree_scene.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;
using isotrace::testing::EmbreeScene;

namespace {


const char* kTwoSpheres = R"({"type": "union", "of": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5},
                                                      {"type": "sphere", "center": [3, 0, 0], "radius": 0.5}]})";

}  // namespace

TEST(EmbreeImplicitGeometry, ReportsNearestHitWithGradientNormal) {
    ImplicitSurface surface(compileField(kTwoSpheres));
    EmbreeScene scene;
    const unsigned id = scene.attach(surface);
    scene.commit();
    const auto h = scene.intersect(Vec3(-2, 0.1, 0), Vec3(1, 0, 0));
    ASSERT_TRUE(h.hit);
    EXPECT_EQ(h.geomID, id);
    const double expected = 2.0 - std::sqrt(0.25 - 0.01);
    EXPECT_NEAR(h.t, expected, 1e-5);
    const Vec3 p = Vec3(-2, 0.1, 0) + h.t * Vec3(1, 0, 0);
    EXPECT_LT((h.normal.normalized() - p.normalized()).norm(), 1e-4);
}

TEST(EmbreeImplicitGeometry, HonoursTnearAndTfar) {
    ImplicitSurface surface(compileField(kTwoSpheres));
    EmbreeScene scene;
    scene.attach(surface);
    scene.commit();
    EXPECT_FALSE(scene.intersect(Vec3(-2, 0, 0), Vec3(1, 0, 0), 0.0, 1.4).hit);
    const auto second = scene.intersect(Vec3(-2, 0, 0), Vec3(1, 0, 0), 2.6);  // past the first sphere
    ASSERT_TRUE(second.hit);
    EXPECT_NEAR(second.t, 4.5, 1e-5);
}

TEST(EmbreeImplicitGeometry, HonoursRayMasks) {
    ImplicitSurface surface(compileField(kTwoSpheres));
    EmbreeScene scene;
    scene.attach(surface, 0x1u);
    scene.commit();
    EXPECT_TRUE(scene.intersect(Vec3(-2, 0, 0), Vec3(1, 0, 0), 0.0, INFINITY, 0x1u).hit);
    EXPECT_FALSE(scene.intersect(Vec3(-2, 0, 0), Vec3(1, 0, 0), 0.0, INFINITY, 0x2u).hit);
}

TEST(EmbreeImplicitGeometry, OcclusionStopsAtTheFirstHitWithinTfar) {
    ImplicitSurface surface(compileField(kTwoSpheres));
    EmbreeScene scene;
    scene.attach(surface);
    scene.commit();
    EXPECT_TRUE(scene.occluded(Vec3(-2, 0, 0), Vec3(1, 0, 0), 10.0));
    EXPECT_FALSE(scene.occluded(Vec3(-2, 0, 0), Vec3(1, 0, 0), 1.4));
    EXPECT_FALSE(scene.occluded(Vec3(-2, 2, 0), Vec3(1, 0, 0), 10.0));
}

namespace {
// Rejects every hit on the first sphere (x < 1.5): traversal must continue.
void rejectFirstSphere(const RTCFilterFunctionNArguments* args) {
    const RTCRay* ray = reinterpret_cast<const RTCRay*>(args->ray);
    const double x = ray->org_x + ray->tfar * ray->dir_x;
    if (x < 1.5) args->valid[0] = 0;
}
}  // namespace

TEST(EmbreeImplicitGeometry, CallsTheFilterForEachCandidate) {
    ImplicitSurface surface(compileField(kTwoSpheres));
    EmbreeScene scene(RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    scene.attach(surface);
    scene.commit();
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.filter = rejectFirstSphere;
    const auto h = scene.intersect(Vec3(-2, 0, 0), Vec3(1, 0, 0), 0.0, INFINITY, 0xFFFFFFFFu, &context);
    ASSERT_TRUE(h.hit);
    EXPECT_NEAR(h.t, 4.5, 1e-5);
}

TEST(EmbreeImplicitGeometry, InstancesShareOneSurfaceAndReportTheirId) {
    ImplicitSurface surface(compileField(R"({"type": "sphere", "radius": 1})"));
    EmbreeScene top;
    RTCScene shape = rtcNewScene(top.device());
    attachImplicitSurface(top.device(), shape, surface);
    rtcCommitScene(shape);
    // Two instances: one moved to x = 5 and scaled by 2.
    for (int i = 0; i < 2; ++i) {
        RTCGeometry inst = rtcNewGeometry(top.device(), RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, shape);
        Eigen::Matrix<float, 3, 4> m = Eigen::Matrix<float, 3, 4>::Zero();
        m.leftCols<3>() = (i == 0 ? 1.0f : 2.0f) * Eigen::Matrix3f::Identity();
        m(0, 3) = i == 0 ? 0.0f : 5.0f;
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
        rtcCommitGeometry(inst);
        rtcAttachGeometryByID(top.scene(), inst, 10 + i);
        rtcReleaseGeometry(inst);
    }
    top.commit();
    const auto a = top.intersect(Vec3(0, 0, -5), Vec3(0, 0, 1));
    ASSERT_TRUE(a.hit);
    EXPECT_EQ(a.instID, 10u);
    EXPECT_NEAR(a.t, 4.0, 1e-5);
    const auto b = top.intersect(Vec3(5, 0, -5), Vec3(0, 0, 1));
    ASSERT_TRUE(b.hit);
    EXPECT_EQ(b.instID, 11u);
    EXPECT_NEAR(b.t, 3.0, 1e-5);
    // The normal is in object space; the host applies the instance transform.
    EXPECT_LT((b.normal.normalized() - Vec3(0, 0, -1)).norm(), 1e-4);
    rtcReleaseScene(shape);
}
