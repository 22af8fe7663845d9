#include "renderer/scene_builder.h"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>

#include "renderer/render.h"
#include "support/compile_field.h"

using namespace isotrace;
using isotrace::testing::compileField;

// A scene made in code, with no file: a unit sphere of albedo 0.5 in a
// uniform environment of radiance 1, seen by a camera that it fills. The
// path tracer's answer has a closed form: a convex object of albedo a in a
// uniform environment reflects a (one bounce; it cannot see itself).
TEST(SceneBuilder, BuildsAScenePieceByPieceThatRendersToItsClosedForm) {
    SceneBuilder builder;
    CameraSettings camera;
    camera.from = Vec3(0, 0, 3);
    camera.to = Vec3(0, 0, 0);
    camera.verticalFovDegrees = 10;
    builder.setCamera(camera);
    FilmSettings film;
    film.width = film.height = 4;
    film.samplesPerPixel = 64;
    builder.setFilm(film);
    builder.setIntegrator(geometry::Json{{"type", "path"}, {"max_depth", 5}});
    SceneObject ball;
    ball.kind = SceneObject::Kind::Implicit;
    ball.material = builder.addMaterial("grey", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}});
    ball.shape = builder.addSurface(
        std::make_unique<geometry::ImplicitSurface>(compileField(R"({"type": "sphere", "radius": 1})")));
    builder.addObject(ball);
    builder.addLight({{"type", "environment"}, {"radiance", {1, 1, 1}}});
    EXPECT_TRUE(builder.hasEnvironment());
    const std::unique_ptr<Scene> scene = builder.build();
    EXPECT_STREQ(scene->integrator->typeName(), "path");
    ASSERT_EQ(scene->lights.size(), 1u);
    const Image image = render(*scene, {.seed = 3, .quiet = true});
    // Environment sampling and BSDF sampling combined by MIS: an unbiased
    // estimate whose mean over 1,024 samples has a standard error near 0.015.
    double mean = 0;
    for (float v : image.rgb) mean += v;
    mean /= double(image.rgb.size());
    EXPECT_NEAR(mean, 0.5, 0.05);
}

TEST(SceneBuilder, EmittersBecomeAreaLightsAndMisuseIsAnInternalError) {
    SceneBuilder builder;
    TriangleMesh quad;
    quad.positions = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
    quad.indices = {0, 1, 2, 0, 2, 3};
    Emission e;
    e.radiance = RGB::Constant(2);
    builder.addEmitter(std::move(quad), e, "panel");
    SceneObject nowhere;
    nowhere.shape = 7;  // no such mesh
    EXPECT_THROW(builder.addObject(nowhere), std::logic_error);
    builder.addMaterial("grey", {{"type", "diffuse"}});
    EXPECT_THROW(builder.addMaterial("grey", {{"type", "mirror"}}), std::logic_error);
    EXPECT_THROW(builder.addMaterial("bad", {{"type", "difuse"}}), geometry::InputError);
    const std::unique_ptr<Scene> scene = builder.build();
    ASSERT_EQ(scene->lights.size(), 1u);
    EXPECT_EQ(scene->objects[0].areaLight, 0);
    // Seen from above its centre, a uniform emitter of area 1 at distance d
    // is sampled with solid-angle density d^2 / (cos * area).
    EXPECT_NEAR(scene->lights[0]->pdf({Vec3(0.5, -2, 0.5)}, Vec3(0, 1, 0), Vec3(0.5, 0, 0.5), Vec3(0, 1, 0)), 4.0, 1e-12);
}
