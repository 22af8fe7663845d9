#include "renderer/lights/mirror_image_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>

#include "renderer/integrator.h"
#include "renderer/scene_builder.h"
#include "support/chi_square.h"
#include "support/polygon_irradiance.h"

using namespace isotrace;
using isotrace::testing::directionChiSquare;
using isotrace::testing::polygonIrradiance;

namespace {

constexpr double kAlbedo = 0.5, kReflectance = 0.8;

TriangleMesh horizontalSquare(double y, double halfWidth, double centerX = 0.0) {
    TriangleMesh mesh;
    const float h = float(y), a = float(centerX - halfWidth), b = float(centerX + halfWidth), w = float(halfWidth);
    mesh.positions = {a, h, -w, b, h, -w, b, h, w, a, h, w};
    mesh.indices = {0, 2, 1, 0, 3, 2};
    return mesh;
}

// A diffuse ceiling at y = 2 facing down, a mirror floor (reflectance 0.8)
// at y = 0 (120 m wide, or `mirrorHalfWidth` centred on `mirrorX`), and what
// the test adds. Paths stop after the light reached by one mirror bounce,
// so the ceiling shows direct light and light seen once in the mirror.
std::unique_ptr<Scene> ceilingOverMirror(const char* integrator, const std::function<void(SceneBuilder&)>& add,
                                         double mirrorHalfWidth = 60, double mirrorX = 0) {
    SceneBuilder builder;
    builder.setIntegrator(geometry::Json{{"type", integrator}, {"max_depth", 2}});
    SceneObject ceiling;
    ceiling.material = builder.addMaterial("ceiling", {{"type", "diffuse"}, {"albedo", {kAlbedo, kAlbedo, kAlbedo}}});
    ceiling.shape = builder.addMesh(horizontalSquare(2, 60));
    builder.addObject(ceiling);
    SceneObject mirror;
    mirror.material =
        builder.addMaterial("mirror", {{"type", "mirror"}, {"reflectance", {kReflectance, kReflectance, kReflectance}}});
    mirror.shape = builder.addMesh(horizontalSquare(0, mirrorHalfWidth, mirrorX));
    builder.addObject(mirror);
    add(builder);
    return builder.build();
}

// The ceiling's mean green radiance at (x, 2, 0), seen from just below.
double ceilingRadiance(const Scene& scene, double x, int samples = 1024, uint64_t seed = 3) {
    Sampler sampler(SamplerType::Sobol, seed);
    double sum = 0.0;
    for (int s = 0; s < samples; ++s) {
        sampler.startPixelSample(0, 0, s);
        sum += scene.integrator->radiance(scene, Ray{Vec3(x, 1.9, 0), Vec3(0, 1, 0)}, sampler)[1];
    }
    return sum / samples;
}

// A 1 m^2 quad light at y = 1 facing down: the ceiling sees only its back,
// so all its light comes by way of the mirror, from its image at y = -1.
const geometry::Json kQuadFacingDown = {{"type", "quad"},         {"corner", {-0.5, 1, -0.5}}, {"edge1", {1, 0, 0}},
                                        {"edge2", {0, 0, 1}},     {"radiance", {25, 25, 25}}};

}  // namespace

// The closed form: the ceiling receives kReflectance times the irradiance of
// the quad's image (Lambert's polygon formula). The path tracer sums two
// strategies by MIS, the image sampled by the light sampler and BSDF samples
// that bounce off the mirror into the quad, so a wrong weight on either
// shifts the mean; the Whitted preview sees the image only. From 1.5 m out
// the straight leg to the mirror passes beside the quad.
TEST(MirrorImageLight, QuadSeenInAMirrorMatchesThePolygonFormula) {
    const std::vector<Vec3> image{Vec3(-0.5, -1, -0.5), Vec3(0.5, -1, -0.5), Vec3(0.5, -1, 0.5), Vec3(-0.5, -1, 0.5)};
    for (const char* integrator : {"path", "whitted"}) {
        const auto scene = ceilingOverMirror(integrator, [](SceneBuilder& b) { b.addLight(kQuadFacingDown); });
        ASSERT_EQ(scene->planeMirrors.size(), 1u);
        for (double x : {1.5, 3.0, 6.0}) {
            const double expected =
                kAlbedo / std::numbers::pi * kReflectance * polygonIrradiance(Vec3(x, 2, 0), Vec3(0, -1, 0), image, 25);
            EXPECT_NEAR(ceilingRadiance(*scene, x), expected, 0.01 * expected) << integrator << " at x = " << x;
        }
    }
}

// A point light is a delta light: BSDF samples never find it in a mirror,
// its image is the only way its reflection lights anything. Direct light
// I cos / d^2 plus the image's, at the unfolded distance. The Whitted
// preview takes every light at every point, so it is exact; the path
// tracer picks one of the two per sample (stratified over 1,024).
TEST(MirrorImageLight, PointLightSeenInAMirrorLightsTheCeiling) {
    const double intensity = 10;
    for (const char* integrator : {"path", "whitted"}) {
        const auto scene = ceilingOverMirror(integrator, [&](SceneBuilder& b) {
            b.addLight({{"type", "point"}, {"position", {0, 1, 0}}, {"intensity", {intensity, intensity, intensity}}});
        });
        for (double x : {0.5, 2.0, 5.0}) {
            const double direct = intensity / std::pow(x * x + 1, 1.5);
            const double mirrored = kReflectance * intensity * 3 / std::pow(x * x + 9, 1.5);
            const double expected = kAlbedo / std::numbers::pi * (direct + mirrored);
            const double tolerance = std::string(integrator) == "path" ? 0.005 : 1e-4;
            EXPECT_NEAR(ceilingRadiance(*scene, x), expected, tolerance * expected) << integrator << " at x = " << x;
        }
    }
}

// The image lights only through the mirror: a mirror off to the side (no
// line from the ceiling to the image crosses it) adds nothing, and neither
// does one whose way to the light is blocked.
TEST(MirrorImageLight, NoLightWhereTheMirrorIsNotOrTheWayIsBlocked) {
    const geometry::Json point = {{"type", "point"}, {"position", {0, 1, 0}}, {"intensity", {10, 10, 10}}};
    const double direct = kAlbedo / std::numbers::pi * 10 / std::pow(2.0 * 2.0 + 1, 1.5);
    for (const char* integrator : {"path", "whitted"}) {
        const double tolerance = std::string(integrator) == "path" ? 0.005 : 1e-4;
        const auto aside = ceilingOverMirror(integrator, [&](SceneBuilder& b) { b.addLight(point); }, 5, 100);
        ASSERT_EQ(aside->planeMirrors.size(), 1u);
        EXPECT_NEAR(ceilingRadiance(*aside, 2.0), direct, tolerance * direct) << integrator;
        // A black plate between the light and the mirror.
        const auto blocked = ceilingOverMirror(integrator, [&](SceneBuilder& b) {
            b.addLight(point);
            SceneObject plate;
            plate.material = b.addMaterial("black", {{"type", "diffuse"}, {"albedo", {0, 0, 0}}});
            plate.shape = b.addMesh(horizontalSquare(0.5, 0.6));
            b.addObject(plate);
        });
        // The direct light passes beside the plate; the way through the
        // mirror meets it at x = 1/3 (mirror point x = 2/3).
        EXPECT_NEAR(ceilingRadiance(*blocked, 2.0), direct, tolerance * direct) << integrator;
    }
}

// Only flat, flat-shaded meshes whose material is a single delta
// reflection are plane mirrors; lights across the plane have no image.
TEST(MirrorImageLight, PlaneMirrorsAreFlatMeshesThatOnlyReflect) {
    auto count = [](const geometry::Json& material, TriangleMesh mesh, const geometry::Json& light) {
        SceneBuilder b;
        SceneObject o;
        o.material = b.addMaterial("m", material);
        o.shape = b.addMesh(std::move(mesh));
        b.addObject(o);
        b.addLight(light);
        const auto scene = b.build();
        return std::pair{scene->planeMirrors.size(), scene->lights.size()};
    };
    const geometry::Json mirror = {{"type", "mirror"}};
    const geometry::Json point = {{"type", "point"}, {"position", {0, 1, 0}}};
    EXPECT_EQ(count(mirror, horizontalSquare(0, 1), point), std::pair(size_t(1), size_t(2)));
    EXPECT_EQ(count({{"type", "conductor"}, {"roughness", 0}}, horizontalSquare(0, 1), point), std::pair(size_t(1), size_t(2)));
    EXPECT_EQ(count({{"type", "conductor"}, {"roughness", 0.2}}, horizontalSquare(0, 1), point), std::pair(size_t(0), size_t(1)));
    EXPECT_EQ(count({{"type", "diffuse"}}, horizontalSquare(0, 1), point), std::pair(size_t(0), size_t(1)));
    EXPECT_EQ(count({{"type", "dielectric"}}, horizontalSquare(0, 1), point), std::pair(size_t(0), size_t(1)));
    TriangleMesh bent = horizontalSquare(0, 1);
    bent.positions[7] = 0.1f;  // one corner lifted
    EXPECT_EQ(count(mirror, bent, point), std::pair(size_t(0), size_t(1)));
    TriangleMesh smooth = horizontalSquare(0, 1);
    smooth.normals = {0, 1, 0, 0, 1, 0, 0.1f, 1, 0, 0, 1, 0};  // a tilted vertex normal
    EXPECT_EQ(count(mirror, smooth, point), std::pair(size_t(0), size_t(1)));
    // A point light in the plane, and an environment: no image.
    EXPECT_EQ(count(mirror, horizontalSquare(0, 1), {{"type", "point"}, {"position", {0, 0, 0}}}),
              std::pair(size_t(1), size_t(1)));
    EXPECT_EQ(count(mirror, horizontalSquare(0, 1), {{"type", "environment"}}), std::pair(size_t(1), size_t(1)));
}

// The image's sampling routine against its density: directions at a point
// towards a 4 x 4 m quad's image, from the point's reflection, by area.
TEST(MirrorImageLight, SamplingPassesChiSquareAgainstItsPdf) {
    const auto scene = ceilingOverMirror("path", [](SceneBuilder& b) {
        b.addLight({{"type", "quad"}, {"corner", {-2, 1, -2}}, {"edge1", {4, 0, 0}}, {"edge2", {0, 0, 4}}});
    });
    ASSERT_EQ(scene->lights.size(), 2u);
    const Light& image = *scene->lights[scene->planeMirrors[0].imageOfLight[0]];
    const LightSampleContext context{Vec3(0.3, 2, 0.1), Vec3(0, -1, 0)};
    // The real point on the quad for a direction at the context.
    auto onLight = [&](const Vec3& w) -> std::optional<Vec3> {
        const Vec3 reflected(w.x(), -w.y(), w.z());
        const Vec3 from(context.p.x(), -context.p.y(), context.p.z());
        if (!(reflected.y() > 0)) return std::nullopt;
        const Vec3 q = from + (1 - from.y()) / reflected.y() * reflected;
        if (std::abs(q.x()) > 2 || std::abs(q.z()) > 2) return std::nullopt;
        return q;
    };
    Sampler sampler(SamplerType::Independent, 6);
    const auto result = directionChiSquare<Vec3>(
        200000,
        [&](int i) {
            sampler.startPixelSample(i, 0, 0);
            const LightSample s = image.sample(context, sampler.get2D());
            if (!(s.pdf > 0)) return Vec3(Vec3::Zero());
            EXPECT_EQ(s.mirror, 0);
            EXPECT_NEAR((s.point - context.p).norm(), s.distance, 1e-9);
            const auto q = onLight(s.direction);
            EXPECT_TRUE(q.has_value());
            if (q) {
                EXPECT_NEAR(image.pdf(context, s.direction, *q, Vec3(0, -1, 0)), s.pdf, 1e-6 * s.pdf);
            }
            return s.direction;
        },
        [&](const Vec3& w) {
            const auto q = onLight(w);
            return q ? image.pdf(context, w, *q, Vec3(0, -1, 0)) : 0.0;
        },
        40, 80, 8);
    EXPECT_EQ(result.impossible, 0.0);
    EXPECT_GT(result.pValue, 0.01) << "chi2 " << result.statistic << " with " << result.degreesOfFreedom << " dof";
}
