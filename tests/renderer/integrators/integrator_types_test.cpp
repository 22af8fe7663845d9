// Properties every integrator type must have, checked over the catalog
// (tests/support/plugin_catalog.h): what a camera ray sees directly is
// exact, whatever else the integrator does with indirect light.
#include <gtest/gtest.h>

#include <numbers>

#include "renderer/integrator.h"
#include "renderer/scene_builder.h"
#include "support/floor_scene.h"
#include "support/plugin_catalog.h"

using namespace isotrace;
using namespace isotrace::testing;

TEST(PluginCatalog, CoversEveryRegisteredIntegratorType) {
    EXPECT_EQ(missingFrom(integratorCatalog(), integratorRegistry().names()), std::vector<std::string>{})
        << "add the new integrator type to tests/support/plugin_catalog.h";
}

namespace {

class EveryIntegrator : public ::testing::TestWithParam<PluginEntry> {};

RGB radianceAlong(const Scene& scene, const Ray& ray, int sample) {
    Sampler sampler(SamplerType::Sobol, 11);
    sampler.startPixelSample(3, 4, sample);
    return scene.integrator->radiance(scene, ray, sampler);
}

}  // namespace

// A ray that leaves an empty scene sees the environment's radiance itself.
TEST_P(EveryIntegrator, RaysThatMissEverythingSeeTheEnvironment) {
    SceneBuilder builder;
    builder.setIntegrator(GetParam().description);
    builder.addLight(geometry::Json{{"type", "environment"}, {"radiance", {0.5, 0.6, 0.7}}});
    const std::unique_ptr<Scene> scene = builder.build();
    for (int s = 0; s < 16; ++s) {
        const Vec3 direction = Vec3(std::sin(s), 0.3 * s - 2, std::cos(3.0 * s)).normalized();
        const RGB L = radianceAlong(*scene, Ray{Vec3(0.1, 0.2, 0.3), direction}, s);
        EXPECT_DOUBLE_EQ(L[0], 0.5);
        EXPECT_DOUBLE_EQ(L[1], 0.6);
        EXPECT_DOUBLE_EQ(L[2], 0.7);
    }
}

// A diffuse floor of albedo 0.5 under a directional light of irradiance 2
// falling straight down, with nothing else: its radiance is the closed form
// albedo E / pi from every sample (the light is a delta, and no other path
// carries light), seen from any direction.
TEST_P(EveryIntegrator, DirectLightOnADiffuseFloorIsTheClosedForm) {
    const std::unique_ptr<Scene> scene = floorScene(GetParam().description, 0.0, [](SceneBuilder& builder) {
        builder.addLight(geometry::Json{{"type", "directional"}, {"direction", {0, -1, 0}}, {"irradiance", {2, 2, 2}}});
    });
    const double expected = 0.5 * 2 / std::numbers::pi;
    for (int s = 0; s < 16; ++s) {
        const Vec3 direction = Vec3(0.2 * std::sin(s), -1, 0.3 * std::cos(s)).normalized();
        const RGB L = radianceAlong(*scene, Ray{Vec3(0.3, 1.5, -0.2), direction}, s);
        EXPECT_NEAR(L[1], expected, 1e-9 * expected) << "sample " << s;
    }
}

INSTANTIATE_TEST_SUITE_P(Catalog, EveryIntegrator, ::testing::ValuesIn(integratorCatalog()),
                         [](const auto& info) { return info.param.name; });
