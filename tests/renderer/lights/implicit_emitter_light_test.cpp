#include "renderer/lights/implicit_emitter_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "renderer/render.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_loader.h"
#include "support/compile_field.h"
#include "support/floor_scene.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::compileField;
using isotrace::testing::loadSceneText;
using isotrace::testing::TemporaryFolder;

namespace {

// An emissive implicit `field` (placed by `placement`) over the floor y = -1.
std::unique_ptr<Scene> floorUnder(const std::string& field, const char* integrator, double radiance,
                                  const Mat4& placement = Mat4::Identity()) {
    return isotrace::testing::floorScene(integrator, -1.0, [&](SceneBuilder& builder) {
        SceneObject lamp;
        lamp.kind = SceneObject::Kind::Implicit;
        lamp.material = builder.addMaterial("glow", {{"type", "emissive"}, {"radiance", {radiance, radiance, radiance}}});
        lamp.shape = builder.addSurface(std::make_unique<geometry::ImplicitSurface>(compileField(field)));
        lamp.worldFromObject = placement;
        builder.addObject(lamp);
    });
}

}  // namespace

// A sphere of radius r and radiance L, its centre at distance d straight
// above a floor point, gives it irradiance pi L (r/d)^2 (the sphere's whole
// disc lies above the floor's horizon). The floor shows rho / pi of it.
// Placed by a transform, so the light's object-space tracing is exercised.
TEST(ImplicitEmitterLight, SphereIrradianceIsPiLTimesRadiusOverDistanceSquared) {
    Mat4 up = Mat4::Identity();
    up(1, 3) = 2.0;  // centre at (0, 2, 0): d = 3 from the floor point below it
    for (const char* integrator : {"path", "whitted"}) {
        const auto scene = floorUnder(R"({"type": "sphere", "radius": 0.5})", integrator, 10.0, up);
        ASSERT_EQ(scene->lights.size(), 1u);
        const double expected = 0.5 / std::numbers::pi * std::numbers::pi * 10.0 * (0.25 / 9.0);
        // The sphere fills a third of the cone of its bounds' sphere, so a
        // light sample's estimate is 0 or 3x the mean; 16,384 stratified
        // samples keep the error well under 1%.
        EXPECT_NEAR(isotrace::testing::radianceLookingDown(*scene, Vec3(0, -0.5, 0), 16384, 23), expected, 0.01 * expected)
            << integrator;
    }
}

// Samples carry the density pdf() gives; the points they reach lie on the
// surface; a sample that brings light comes from a light with importance.
TEST(ImplicitEmitterLight, SamplesAgreeWithPdfAndLieOnTheSurface) {
    const auto scene = floorUnder(R"({"type": "torus", "major": 0.8, "minor": 0.3})", "path", 3.0);
    const Light& light = *scene->lights[0];
    const geometry::FieldProgram torus = compileField(R"({"type": "torus", "major": 0.8, "minor": 0.3})");
    Sampler sampler(SamplerType::Sobol, 2);
    int hits = 0;
    for (const Vec3& p : {Vec3(0, -1, 0), Vec3(3, -1, 0.5), Vec3(0, 0, 0)}) {
        const LightSampleContext context{p, p.isZero() ? Vec3::Zero() : Vec3(0, 1, 0)};
        for (int s = 0; s < 256; ++s) {
            sampler.startPixelSample(0, s, 0);
            const LightSample ls = light.sample(context, sampler.get2D());
            ASSERT_GT(ls.pdf, 0.0);
            EXPECT_NEAR(light.pdf(context, ls.direction, ls.point, Vec3::Zero()), ls.pdf, 1e-12 * ls.pdf);
            if (!(ls.radiance > 0).any()) continue;
            ++hits;
            EXPECT_LT(std::abs(torus.value(ls.point)), 1e-4);
            EXPECT_GT(light.importance(context), 0.0);
        }
    }
    EXPECT_GT(hits, 100);
}

// An emissive tangle lights a floor as its polygonized mesh does: the mean
// floor radiance of the two renders agrees within the noise measured
// between two seeds of the implicit render.
TEST(ImplicitEmitterLight, EmissiveTangleLightsTheFloorAsItsMeshDoes) {
    TemporaryFolder folder;
    const std::string scene = R"({"camera": {"from": [0, 4, 9], "to": [0, -1, 0], "fov": 50},
      "film": {"width": 24, "height": 16, "spp": 64},
      "integrator": {"type": "path", "max_depth": 2},
      "materials": {"grey": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}, "glow": {"type": "emissive", "radiance": [2, 2, 2]}},
      "fields": {"tangle": {"type": "polynomial", "preset": "tangle"}},
      "objects": [{"field": "tangle", "material": "glow", "resolution": 160, "transform": {"scale": 0.4, "translate": [0, 0.5, 0]}},
                  {"vertices": [-9, -1, -9, 9, -1, -9, 9, -1, 9, -9, -1, 9], "indices": [0, 2, 1, 0, 3, 2], "material": "grey"}]})";
    SceneOverrides asMesh;
    asMesh.fieldMode = SceneOverrides::FieldMode::Mesh;
    const auto implicit = loadSceneText(folder, scene), mesh = loadSceneText(folder, scene, asMesh);
    auto floorMean = [](const Image& image) {
        double sum = 0;
        int n = 0;
        for (int y = image.height / 2; y < image.height; ++y)  // the lower half: floor
            for (int x = 0; x < image.width; ++x) sum += image.pixel(x, y)[1], ++n;
        return sum / n;
    };
    const double a = floorMean(render(*implicit, {.seed = 1, .quiet = true}));
    const double b = floorMean(render(*implicit, {.seed = 2, .quiet = true}));
    const double m = floorMean(render(*mesh, {.seed = 3, .quiet = true}));
    const double noise = std::max(std::abs(a - b), 1e-3 * a);
    EXPECT_GT(a, 0.01);
    EXPECT_NEAR(m, 0.5 * (a + b), 4.0 * noise) << "implicit " << a << ", " << b << "; mesh " << m;
}
