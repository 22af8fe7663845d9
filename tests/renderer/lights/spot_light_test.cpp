// Spot lights against the closed form of Blender 3.4's spot: a diffuse
// floor under a spot pointing straight down has irradiance
// I cos(theta) s(theta) cos(theta) / d^2, where s is 1 inside the cone,
// smoothstep across the blend and 0 outside.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "renderer/scene_builder.h"
#include "support/floor_scene.h"

using namespace isotrace;
using namespace isotrace::testing;

namespace {

constexpr double kHeight = 2.0, kIntensity = 3.0, kConeDegrees = 60.0, kBlend = 0.2;

std::unique_ptr<Scene> floorUnderSpot() {
    return floorScene("path", 0.0, [](SceneBuilder& builder) {
        builder.addLight(geometry::Json{{"type", "spot"},
                                        {"position", {0, kHeight, 0}},
                                        {"direction", {0, -1, 0}},
                                        {"intensity", {kIntensity, kIntensity, kIntensity}},
                                        {"cone_angle", kConeDegrees},
                                        {"blend", kBlend}});
    });
}

// The floor's radiance at the point where the light's ray at cos(theta)
// to the axis lands, for a spot factor s (albedo 0.5).
struct FloorPoint {
    double x, expected;
};
FloorPoint floorPointAt(double cosTheta, double spotFactor) {
    const double tangent = std::sqrt(1 - cosTheta * cosTheta) / cosTheta;
    const double d2 = kHeight * kHeight * (1 + tangent * tangent);
    return {kHeight * tangent, 0.5 / std::numbers::pi * kIntensity * cosTheta * spotFactor * cosTheta / d2};
}

}  // namespace

TEST(SpotLight, LightsTheFloorAsBlendersSpotDoes) {
    const auto scene = floorUnderSpot();
    const double cosHalf = std::cos(kConeDegrees / 2 * std::numbers::pi / 180), smooth = (1 - cosHalf) * kBlend;
    const FloorPoint points[] = {
        floorPointAt(1.0, 1.0),                       // on the axis
        floorPointAt(cosHalf + 1.5 * smooth, 1.0),    // inside, short of the blend
        floorPointAt(cosHalf + 0.5 * smooth, 0.5),    // halfway across the blend: smoothstep(1/2)
        floorPointAt(cosHalf + 0.25 * smooth, 0.15625),  // a quarter: 3/16 - 2/64
        floorPointAt(cosHalf - 0.01, 0.0),            // outside the cone
    };
    for (const FloorPoint& p : points) {
        const double L = radianceLookingDown(*scene, Vec3(p.x, 1.0, 0.0), 4, 3);
        EXPECT_NEAR(L, p.expected, 1e-9 + 1e-9 * p.expected) << "x = " << p.x;
    }
    EXPECT_GT(points[3].expected, 0.0);
}

// Light choice follows the spot: nothing where its cone does not reach, and
// the irradiance itself where it does.
TEST(SpotLight, ImportanceIsZeroOutsideTheConeAndTheIrradianceInside) {
    const auto scene = floorUnderSpot();
    const Light& spot = *scene->lights[0];
    const FloorPoint inside = floorPointAt(0.95, 1.0);
    EXPECT_NEAR(spot.importance({Vec3(inside.x, 0, 0), Vec3(0, 1, 0)}), inside.expected * std::numbers::pi / 0.5,
                1e-12);
    EXPECT_EQ(spot.importance({Vec3(5, 0, 0), Vec3(0, 1, 0)}), 0.0);
    EXPECT_EQ(spot.importance({Vec3(0, 3, 0), Vec3(0, -1, 0)}), 0.0);  // above the light
}
