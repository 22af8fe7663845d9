#include "renderer/light_sampler.h"

#include <gtest/gtest.h>

#include <numbers>

#include "renderer/scene_builder.h"

using namespace isotrace;

namespace {

// A scene of one small shape and the given lights.
std::unique_ptr<Scene> shapeWith(const std::vector<geometry::Json>& lights, const char* sampling = "tree") {
    SceneBuilder builder;
    builder.setIntegrator(geometry::Json{{"type", "path"}, {"light_sampler", sampling}});
    SceneObject shape;
    shape.material = builder.addMaterial("grey", {{"type", "diffuse"}});
    TriangleMesh triangle;
    triangle.positions = {1, 0, 0, -1, 0, 0, 0, 1, 0};
    triangle.indices = {0, 1, 2};
    shape.shape = builder.addMesh(std::move(triangle));
    builder.addObject(shape);
    for (const auto& l : lights) builder.addLight(l);
    return builder.build();
}

}  // namespace

// Importance estimates irradiance: I cos / d^2 for a point light, and for a
// small one-sided quad L A cos cos / d^2 with the cosines bounded over the
// quad's extent; nothing behind a surface or a one-sided emitter.
TEST(LightSampler, ImportanceFollowsDistanceAndOrientation) {
    const auto scene = shapeWith({{{"type", "point"}, {"position", {0, 4, 0}}, {"intensity", {2, 2, 2}}},
                                  {{"type", "quad"}, {"corner", {9.95, 4, -0.05}}, {"edge1", {0.1, 0, 0}},
                                   {"edge2", {0, 0, 0.1}}, {"radiance", {100, 100, 100}}}});
    const Light& point = *scene->lights[0];
    const Light& quad = *scene->lights[1];
    const LightSampleContext up{Vec3::Zero(), Vec3(0, 1, 0)}, down{Vec3::Zero(), Vec3(0, -1, 0)};
    EXPECT_NEAR(point.importance(up), 2.0 / 16.0, 1e-12);
    EXPECT_EQ(point.importance(down), 0.0);
    // The quad (area 0.01, at (10, 4, 0), facing down) seen from the origin:
    // both cosines are 4 / sqrt(116) up to the quad's 0.07 m extent.
    const double d2 = 116, c = 4 / std::sqrt(d2);
    EXPECT_NEAR(quad.importance(up), 100 * 0.01 * c * c / d2, 0.03 * 100 * 0.01 / d2);
    EXPECT_GE(quad.importance(up), 100 * 0.01 * c * c / d2);  // a bound, not below the truth
    EXPECT_EQ(quad.importance({Vec3(10, 5, 0), Vec3(0, -1, 0)}), 0.0);  // behind the one-sided quad
}

TEST(LightSampler, ExhaustiveChoosesInProportionToImportance) {
    const auto scene = shapeWith({{{"type", "point"}, {"position", {0, 4, 0}}, {"intensity", {2, 2, 2}}},
                                  {{"type", "point"}, {"position", {0, -4, 0}}, {"intensity", {50, 50, 50}}},
                                  {{"type", "point"}, {"position", {3, 2, 0}}, {"intensity", {1, 1, 1}}}},
                                 "exhaustive");
    const LightSampler& s = scene->lightSampler;
    const LightSampleContext up{Vec3::Zero(), Vec3(0, 1, 0)};
    const double w0 = 2.0 / 16, w2 = 1.0 * (2 / std::sqrt(13.0)) / 13;
    EXPECT_NEAR(s.pmf(up, 0), w0 / (w0 + w2), 1e-12);
    EXPECT_EQ(s.pmf(up, 1), 0.0);  // below the horizon
    EXPECT_NEAR(s.pmf(up, 2), w2 / (w0 + w2), 1e-12);
    int counts[3] = {0, 0, 0};
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        double pmf = 0;
        const int k = s.sample(up, (i + 0.5) / n, pmf);
        ASSERT_GE(k, 0);
        EXPECT_DOUBLE_EQ(pmf, s.pmf(up, k));
        ++counts[k];
    }
    EXPECT_NEAR(counts[0], n * s.pmf(up, 0), 1.0);
    EXPECT_EQ(counts[1], 0);
    EXPECT_NEAR(counts[2], n * s.pmf(up, 2), 1.0);
    double pmf = 0;
    EXPECT_EQ(s.sample(up, 0.9999999999999999, pmf), 2);
    // Facing down, only the bright light below counts.
    EXPECT_EQ(s.sample({Vec3::Zero(), Vec3(0, -1, 0)}, 0.3, pmf), 1);
    EXPECT_EQ(pmf, 1.0);
}

TEST(LightSampler, NoLightThatCanLightThePoint) {
    double pmf = 0;
    EXPECT_EQ(LightSampler().sample({}, 0.5, pmf), -1);
    const auto dark = shapeWith({{{"type", "point"}, {"position", {0, 3, 0}}, {"intensity", {0, 0, 0}}},
                                 {{"type", "directional"}, {"direction", {0, 1, 0}}, {"irradiance", {1, 1, 1}}}});
    EXPECT_EQ(dark->lightSampler.sample({Vec3::Zero(), Vec3(0, 1, 0)}, 0.5, pmf), -1);
}
