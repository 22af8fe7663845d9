// Fields shown "as": "particles": Embree's oriented discs at the particles,
// so rays hit discs lying on the surface, and bad settings name their key.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "renderer/render.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::expectNamedError;
using isotrace::testing::loadSceneText;
using isotrace::testing::sceneError;
using isotrace::testing::TemporaryFolder;

namespace {

std::string particleScene(const std::string& settings) {
    return R"({"camera": {"from": [0, 0, 5], "to": [0, 0, 0]},
      "materials": {"m": {"type": "diffuse"}},
      "fields": {"ball": {"type": "sphere", "radius": 1}},
      "objects": [{"field": "ball", "as": "particles", "material": "m")" + settings + "}]}";
}

}  // namespace

// Discs are tangent to a sphere of radius 1 at points on it: a hit lies
// between 1 and sqrt(1 + r^2) ~ 1 + r^2 / 2 (a disc's rim) from the centre.
// At disc_scale 1.3 (radius 0.65 of the spacing; hexagonal packing is
// covered from 0.577) the discs close the surface: no ray through it escapes.
TEST(ParticleDiscs, RaysHitDiscsLyingOnTheSurface) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, particleScene(R"(, "count": 2000, "seed": 4, "disc_scale": 1.3)"));
    ASSERT_EQ(scene->discs.size(), 1u);
    const size_t count = scene->discs[0]->count();
    EXPECT_NEAR(double(count), 2000, 200);
    double largest = 0;
    for (size_t i = 0; i < count; ++i) largest = std::max(largest, double(scene->discs[0]->centersAndRadii[4 * i + 3]));
    const double sag = 0.5 * largest * largest;
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-0.95, 0.95);
    int hits = 0, rays = 0;
    while (rays < 2000) {
        const Vec3 target(u(rng), u(rng), 0);
        if (target.norm() > 0.95) continue;
        ++rays;
        const Vec3 origin(0, 0, 5);
        SurfaceHit hit;
        if (!scene->intersect(Ray{origin, (target - origin).normalized()}, INFINITY, hit)) continue;
        ++hits;
        const double r = hit.position.norm();
        EXPECT_GT(r, 1 - 1e-5);
        EXPECT_LT(r, 1 + sag + 1e-5);
        EXPECT_NEAR(std::abs(hit.geometricNormal.dot(hit.position.normalized())), 1.0, 0.02) << "the disc's normal";
    }
    EXPECT_GT(double(hits), 0.99 * rays);
}

TEST(ParticleDiscs, BadSettingsNameTheirKey) {
    TemporaryFolder folder;
    expectNamedError(sceneError(folder, particleScene(R"(, "count": 0)")), "/objects/0/count", "between 1 and");
    expectNamedError(sceneError(folder, particleScene(R"(, "count": 10, "spacing": 0.1)")), "/objects/0/count",
                     "not both");
    expectNamedError(sceneError(folder, particleScene(R"(, "spacing": -1)")), "/objects/0/spacing", "greater than 0");
    expectNamedError(sceneError(folder, particleScene(R"(, "spacing": 1e-7)")), "/objects/0", "10 million");
    expectNamedError(sceneError(folder, particleScene(R"(, "disc_scale": 0)")), "/objects/0/disc_scale", "(0, 4]");
    expectNamedError(sceneError(folder, particleScene(R"(, "seed": -2)")), "/objects/0/seed", "between");
}
