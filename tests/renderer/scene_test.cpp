#include "renderer/scene.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/errors.h"
#include "renderer/integrator.h"
#include "renderer/platform/embree_errors.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::loadSceneText;
using isotrace::testing::TemporaryFolder;

namespace {
const char* kShapes = R"({"materials": {"m": {"type": "diffuse"}},
  "fields": {"ball": {"type": "sphere", "radius": 1},
             "blob": {"type": "blobby", "blobs": [{"center": [-0.3, 0, 0], "radius": 1}, {"center": [0.4, 0.1, 0], "radius": 0.9}]}},
  "objects": [{"field": "%FIELD%", "material": "m", "transform": {"translate": [0.5, -0.2, 0.1], "scale": 1.7}}]})";

std::string withField(const std::string& field) {
    std::string s = kShapes;
    s.replace(s.find("%FIELD%"), 7, field);
    return s;
}
}  // namespace

// Rays leaving a convex surface into its outer hemisphere never hit it
// again: no self-intersection acne (the offset origin clears the surface).
TEST(Scene, RaysSpawnedOffAConvexImplicitNeverRehitIt) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, withField("ball"));
    std::mt19937_64 rng(8);
    std::normal_distribution<double> n;
    int hits = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        const Vec3 target = Vec3(0.5, -0.2, 0.1) + 1.7 * Vec3(n(rng), n(rng), n(rng)).normalized();
        const Vec3 origin = target + 6.0 * Vec3(n(rng), n(rng), n(rng)).normalized();
        SurfaceHit hit;
        if (!scene->intersect({origin, (target - origin).normalized()}, INFINITY, hit)) continue;
        ++hits;
        const Vec3 ng = hit.geometricNormal;
        const Vec3 w = sampleCosineHemisphere(ng, {std::uniform_real_distribution<double>()(rng),
                                                   std::uniform_real_distribution<double>()(rng)});
        SurfaceHit again;
        ASSERT_FALSE(scene->intersect({offsetOrigin(hit.position, ng, w), w}, INFINITY, again))
            << "trial " << trial << " re-hit at t=" << again.t;
    }
    EXPECT_GT(hits, 2000);
}

// Rays spawned into the inner side of a surface (refraction, a ray
// starting inside) find the far side, not the point they left.
TEST(Scene, RaysSpawnedInsideFindTheFarSide) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, withField("ball"));
    std::mt19937_64 rng(9);
    std::normal_distribution<double> n;
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec3 c(0.5, -0.2, 0.1);
        const Vec3 p = c + 1.7 * Vec3(n(rng), n(rng), n(rng)).normalized();
        const Vec3 normal = (p - c).normalized();
        const Vec3 w = sampleCosineHemisphere(-normal, {0.3 + 0.4 * (trial % 2), 0.001 * trial});
        SurfaceHit hit;
        ASSERT_TRUE(scene->intersect({offsetOrigin(p, normal, w), w}, INFINITY, hit)) << "trial " << trial;
        // The chord from p along w has length 2 r cos(theta).
        const double chord = 2 * 1.7 * (-normal).dot(w);
        ASSERT_NEAR(hit.t, chord, 1e-3) << "trial " << trial;
    }
}

TEST(Scene, ImplicitNormalsAreOutwardUnitGradientsUnderTransforms) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, withField("blob"));
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect({Vec3(0.5, -0.2, 8), Vec3(0, 0, -1)}, INFINITY, hit));
    EXPECT_NEAR(hit.geometricNormal.norm(), 1.0, 1e-9);
    EXPECT_GT(hit.geometricNormal.z(), 0.5);
}

// A ray Embree would abort on (non-finite, or too far out) leaves the scene.
TEST(Scene, UnrepresentableRaysMissInsteadOfAborting) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, withField("ball"));
    SurfaceHit hit;
    EXPECT_FALSE(scene->intersect({Vec3(0, 0, 5), Vec3(0, 0, NAN)}, INFINITY, hit));
    EXPECT_FALSE(scene->intersect({Vec3(0, 0, 9e18), Vec3(0, 0, -1)}, INFINITY, hit));
    EXPECT_FALSE(scene->occluded(Vec3(0, 0, 5), Vec3(INFINITY, 0, 0), 1.0));
    EXPECT_TRUE(scene->intersect({Vec3(0, 0, 5), Vec3(0, 0, -1)}, INFINITY, hit));
}

// Objects without a transform are attached to the top scene as they are,
// the others through instances, and a field may be placed both ways: each
// hit names the object it hit and lands on that object's sphere, with the
// normal of the sphere there. Analytic truth: ray-sphere distances.
// Implicit and mesh objects with no transform go into the top scene as they
// are; the others are instanced. Either way a hit names its own object and
// lies on its own surface: implicits to their tolerance, the polygonized
// spheres within their triangles' sag, with interpolated normals.
TEST(Scene, ObjectsPlacedAsTheyAreOrInstancedReportTheirOwnHits) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, R"({"materials": {"m": {"type": "diffuse"}},
      "fields": {"ball": {"type": "sphere", "radius": 1}, "small": {"type": "sphere", "center": [0, 3, 0], "radius": 0.5},
                 "low": {"type": "sphere", "center": [0, -3, 0], "radius": 0.5}},
      "objects": [{"field": "ball", "material": "m"},
                  {"field": "ball", "material": "m", "transform": {"translate": [4, 0, 0], "scale": 0.5}},
                  {"field": "small", "material": "m"},
                  {"field": "small", "material": "m", "transform": {"translate": [-4, -3, 0]}},
                  {"field": "low", "as": "mesh", "resolution": 64, "material": "m"},
                  {"field": "ball", "as": "mesh", "resolution": 64, "material": "m",
                   "transform": {"translate": [4, -3, 0], "scale": 0.5}}]})");
    struct Sphere {
        Vec3 center;
        double radius;
        bool mesh;
    };
    const Sphere spheres[6] = {{{0, 0, 0}, 1.0, false},  {{4, 0, 0}, 0.5, false}, {{0, 3, 0}, 0.5, false},
                               {{-4, 0, 0}, 0.5, false}, {{0, -3, 0}, 0.5, true}, {{4, -3, 0}, 0.5, true}};
    std::mt19937_64 rng(11);
    std::normal_distribution<double> n;
    for (int object = 0; object < 6; ++object) {
        const Sphere& s = spheres[object];
        // Triangles of edge h lie within h^2 / (8 r) inside the sphere, and
        // their normals turn by about h / r (64 cells over the bounds).
        const double distanceTolerance = s.mesh ? 2e-3 : 1e-4, normalTolerance = s.mesh ? 2e-3 : 1e-4;
        for (int trial = 0; trial < 200; ++trial) {
            // From outside, towards a point inside the sphere's upper half (z > 0).
            Vec3 inside = 0.5 * s.radius * Vec3(n(rng), n(rng), std::abs(n(rng))).normalized();
            const Vec3 origin = s.center + Vec3(0, 0, 10);
            const Vec3 direction = (s.center + inside - origin).normalized();
            SurfaceHit hit;
            ASSERT_TRUE(scene->intersect({origin, direction}, INFINITY, hit)) << "object " << object;
            EXPECT_EQ(hit.object, object);
            // Entry distance along the ray: the smaller root of |o + t d - c| = r.
            const Vec3 oc = origin - s.center;
            const double b = oc.dot(direction), c = oc.squaredNorm() - s.radius * s.radius;
            const double t = -b - std::sqrt(b * b - c);
            EXPECT_NEAR(hit.t, t, distanceTolerance * s.radius) << "object " << object;
            EXPECT_GT(hit.shadingNormal.dot((hit.position - s.center).normalized()), 1.0 - normalTolerance)
                << "object " << object;
        }
    }
}

// Embree's errors come back as exceptions after the call, never thrown
// through its C callback: a wrong call is an internal error naming what
// was being done, reported once.
TEST(EmbreeErrorRecord, ReportsAWrongCallAfterItAsAnInternalError) {
    RTCDevice device = rtcNewDevice(nullptr);
    ASSERT_NE(device, nullptr);
    {
        EmbreeErrorRecord errors;
        errors.attachTo(device);
        EXPECT_NO_THROW(errors.check("doing nothing"));
        RTCGeometry geometry = rtcNewGeometry(device, RTCGeometryType(999));  // no such type: an invalid argument
        EXPECT_EQ(geometry, nullptr);
        try {
            errors.check("making a geometry");
            ADD_FAILURE() << "no error reported";
        } catch (const geometry::InternalError& e) {
            EXPECT_NE(std::string(e.what()).find("while making a geometry"), std::string::npos) << e.what();
        }
        EXPECT_NO_THROW(errors.check("the same call again")) << "an error is reported once";
        rtcSetDeviceErrorFunction(device, nullptr, nullptr);
    }
    rtcReleaseDevice(device);
}
