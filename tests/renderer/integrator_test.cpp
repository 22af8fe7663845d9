#include "renderer/integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "renderer/render.h"
#include "renderer/scene_builder.h"
#include "support/floor_scene.h"
#include "support/polygon_irradiance.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::floorScene;
using isotrace::testing::radianceLookingDown;
using isotrace::testing::loadSceneText;
using isotrace::testing::polygonIrradiance;
using isotrace::testing::TemporaryFolder;

namespace {

struct PixelStatistics {
    double mean = 0.0, worst = 0.0;
    int count = 0;
};

// Mean of the luminance-free average of channels over pixels passing `keep`,
// and the worst deviation from `expected`.
template <class Keep>
PixelStatistics statistics(const Image& image, double expected, Keep keep) {
    PixelStatistics s;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            if (!keep(x, y)) continue;
            const float* p = image.pixel(x, y);
            const double v = (p[0] + p[1] + p[2]) / 3.0;
            s.mean += v;
            s.worst = std::max(s.worst, std::abs(v - expected));
            ++s.count;
        }
    s.mean /= std::max(1, s.count);
    return s;
}

std::string furnaceScene(const std::string& albedo, const std::string& objects, const std::string& integrator = "path") {
    return R"({"camera": {"from": [0, 0.5, 4], "to": [0, 0, 0], "fov": 40},
      "film": {"width": 32, "height": 32, "spp": 128},
      "integrator": {"type": ")" + integrator + R"(", "max_depth": 100},
      "materials": {"white": {"type": "diffuse", "albedo": )" + albedo + R"(}},
      "fields": {"ball": {"type": "sphere", "radius": 1},
                 "grooved": {"type": "difference", "of": ["ball", {"type": "torus", "major": 0.9, "minor": 0.35}]}},
      "objects": )" + objects + R"(,
      "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
}

// A concave mesh: a box of five faces, open towards the camera, around the
// grooved sphere (with room to spare: a tight wedge would trap paths for
// more than max_depth bounces, a real but truncated contribution).
const char* kOpenBox = R"({"vertices": [-1.5,-1.5,-1.5, 1.5,-1.5,-1.5, 1.5,1.5,-1.5, -1.5,1.5,-1.5,
                                        -1.5,-1.5,1.2, 1.5,-1.5,1.2, 1.5,1.5,1.2, -1.5,1.5,1.2],
  "indices": [0,1,2, 0,2,3, 0,4,5, 0,5,1, 1,5,6, 1,6,2, 2,6,7, 2,7,3, 3,7,4, 3,4,0], "material": "white"})";

}  // namespace

// White furnace: with albedo 1 in a uniform environment of radiance 1, every
// pixel is 1 whatever the geometry. Per-pixel noise at 128 spp measures
// about 0.03 here (seeds 1-3), so the mean of 1,024 pixels has a standard
// error near 0.001: the 0.5% bound is 5 standard errors, and no single
// pixel may stray by 0.25 (8 sigma).
TEST(PathIntegrator, WhiteFurnaceConvexImplicit) {
    TemporaryFolder folder;
    const Image image = render(*loadSceneText(folder, furnaceScene("[1, 1, 1]", R"([{"field": "ball", "material": "white"}])")),
                               {.threads = 2, .seed = 1, .quiet = true});
    const auto s = statistics(image, 1.0, [](int, int) { return true; });
    EXPECT_NEAR(s.mean, 1.0, 0.005);
    EXPECT_LT(s.worst, 0.25);
}

// A convex object sees only the environment, so one bounce ends every path.
// The environment is sampled cosine-weighted around the normal, with the
// density a Lambertian BSDF samples with: both strategies get MIS weight
// 1/2 and each estimate is exactly the albedo, so every pixel is 1 up to
// rounding, not only on average (uniform sphere sampling left 0.95-1.05).
TEST(PathIntegrator, WhiteFurnaceIsExactInEveryPixelForAConvexObject) {
    TemporaryFolder folder;
    SceneOverrides at16spp;
    at16spp.samplesPerPixel = 16;
    auto scene = loadSceneText(folder, furnaceScene("[1, 1, 1]", R"([{"field": "ball", "material": "white"}])"), at16spp);
    const Image image = render(*scene, {.threads = 2, .seed = 4, .quiet = true});
    double worst = 0.0;
    for (float v : image.rgb) worst = std::max(worst, std::abs(double(v) - 1.0));
    EXPECT_LT(worst, 1e-4);
    std::printf("white furnace, 16 spp: largest deviation of a pixel from 1: %.3g\n", worst);
}

TEST(PathIntegrator, WhiteFurnaceNonConvexImplicitAndMesh) {
    TemporaryFolder folder;
    const std::string objects = std::string(R"([{"field": "grooved", "material": "white"}, )") + kOpenBox + "]";
    const Image image = render(*loadSceneText(folder, furnaceScene("[1, 1, 1]", objects)), {.threads = 2, .seed = 1, .quiet = true});
    const auto s = statistics(image, 1.0, [](int, int) { return true; });
    EXPECT_NEAR(s.mean, 1.0, 0.005);
    EXPECT_LT(s.worst, 0.25);
}

// A convex sphere of albedo 0.8 sees only the environment: its pixels are 0.8.
TEST(PathIntegrator, ConvexSphereOfAlbedo08ConvergesTo08) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, furnaceScene("[0.8, 0.8, 0.8]", R"([{"field": "ball", "material": "white"}])"));
    const Image image = render(*scene, {.threads = 2, .seed = 1, .quiet = true});
    const PerspectiveCamera camera(scene->camera, image.width, image.height);
    // Pixels whose whole filter footprint (radius 1.5 px) lands on the sphere.
    auto onSphere = [&](int x, int y) {
        for (double dx : {-1.6, 1.6})
            for (double dy : {-1.6, 1.6}) {
                const Ray r = camera.generateRay(x + 0.5 + dx, y + 0.5 + dy, {0, 0});
                const double b = r.origin.dot(r.direction), c = r.origin.squaredNorm() - 1.0;
                if (b * b - c < 0) return false;
            }
        return true;
    };
    const auto s = statistics(image, 0.8, onSphere);
    ASSERT_GT(s.count, 100);
    EXPECT_NEAR(s.mean, 0.8, 0.8 * 0.005);
    EXPECT_LT(s.worst, 0.2);
}

namespace {

// Radiance of a diffuse plane y = 0 (albedo rho) lit by a point light: rho/pi * I cos / d^2.
double pointLitPlane(const Vec3& p, const Vec3& light, double intensity, double rho) {
    const Vec3 d = light - p;
    return rho / std::numbers::pi * intensity * (d.y() / d.norm()) / d.squaredNorm();
}

std::string planeScene(const std::string& integrator, const std::string& lights, int size, int spp, const std::string& from,
                       double fov = 30) {
    return R"({"camera": {"from": )" + from + R"(, "to": [0, 0, 0], "fov": )" + std::to_string(fov) + R"(},
      "film": {"width": )" + std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(, "spp": )" +
           std::to_string(spp) + R"(, "filter": {"type": "box", "radius": 0.5}},
      "integrator": {"type": ")" + integrator + R"(", "max_depth": 4},
      "materials": {"grey": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [{"vertices": [-20, 0, -20, 20, 0, -20, 20, 0, 20, -20, 0, 20], "indices": [0, 2, 1, 0, 3, 2], "material": "grey"}],
      "lights": )" + lights + "}";
}

}  // namespace

// A point light over a plane: every pixel matches the closed form at its
// centre. The box-filtered pixel averages a smooth function over 1/33 of the
// view, which moves it from the centre value by well under 0.2%.
TEST(DirectLighting, PointLightOverPlaneMatchesClosedForm) {
    for (const char* integrator : {"path", "whitted"}) {
        TemporaryFolder folder;
        const Vec3 light(0.3, 2.0, -0.2);
        auto scene = loadSceneText(folder, planeScene(integrator, R"([{"type": "point", "position": [0.3, 2, -0.2], "intensity": [10, 10, 10]}])",
                                                      33, 16, "[0, 4, 4]"));
        const Image image = render(*scene, {.threads = 2, .seed = 3, .quiet = true});
        const PerspectiveCamera camera(scene->camera, image.width, image.height);
        int checked = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const Ray r = camera.generateRay(x + 0.5, y + 0.5, {0, 0});
                if (r.direction.y() >= 0) continue;
                const Vec3 p = r.origin - (r.origin.y() / r.direction.y()) * r.direction;
                const double expected = pointLitPlane(p, light, 10.0, 0.5);
                ASSERT_NEAR(image.pixel(x, y)[1], expected, 0.01 * expected) << integrator << " pixel " << x << "," << y;
                ++checked;
            }
        EXPECT_EQ(checked, 33 * 33);
    }
}

// A disk light of radius R at height h facing down: the point below its
// centre receives E = pi L R^2 / (h^2 + R^2), so the plane there shows
// rho L R^2 / (h^2 + R^2). The disk is a 64-gon (0.16% less area than the
// disk); with 4,096 samples the estimate's noise is below 0.3%: 1% bounds both.
// A 1 degree field of view keeps the pixel's footprint on the plane tiny.
TEST(DirectLighting, DiskLightOverPlaneMatchesClosedForm) {
    for (const char* integrator : {"path", "whitted"}) {
        TemporaryFolder folder;
        auto scene = loadSceneText(
            folder, planeScene(integrator, R"([{"type": "disk", "center": [0, 1, 0], "normal": [0, -1, 0], "radius": 0.5, "radiance": [4, 4, 4]}])",
                               9, 4096, "[0, 0.5, 0.8]", 1.0));
        const Image image = render(*scene, {.threads = 2, .seed = 5, .quiet = true});
        const double expected = 0.5 * 4.0 * 0.25 / (1.0 + 0.25);
        EXPECT_NEAR(image.pixel(4, 4)[0], expected, 0.01 * expected) << integrator;
    }
}

// An emissive mesh is a light per triangle: a fan of 64 triangles of many
// sizes facing down, wide and low over the plane, gives 64 lights, and a
// point under it receives what Lambert's polygon formula says. So close,
// BSDF samples carry much of the estimate, and a path that hits a triangle
// is weighed by that triangle's pdf and the tree's pmf of it: mapped to
// another triangle's light, the weights would not sum to one (every hit
// weighed as the first triangle: 1.2% off). With 4,096 samples two seeds
// land within 0.1%; 0.5% is allowed.
TEST(DirectLighting, EmissiveMeshIsALightPerTriangleAndMatchesThePolygonFormula) {
    const int sides = 64;
    const double radius = 2.0, height = 0.3;
    std::vector<Vec3> polygon;
    geometry::Json vertices = {0, height, 0}, indices = geometry::Json::array();
    for (int k = 0; k < sides; ++k) {
        // Uneven angles: triangles of many sizes, so each has its own pdf.
        const double phi = 2.0 * std::numbers::pi * std::pow(double(k) / sides, 1.5);
        polygon.push_back(Vec3(radius * std::cos(phi), height, radius * std::sin(phi)));
        for (double v : {polygon.back().x(), height, polygon.back().z()}) vertices.push_back(v);
        // Wound so that the normal points down, the side that emits.
        for (int i : {0, 1 + k, 1 + (k + 1) % sides}) indices.push_back(i);
    }
    for (const char* integrator : {"path", "whitted"}) {
        TemporaryFolder folder;
        const geometry::Json scene = {
            {"camera", {{"from", {0.3, 0.2, 0.4}}, {"to", {0.3, 0, 0}}, {"fov", 1}}},
            {"film", {{"width", 9}, {"height", 9}, {"spp", 4096}, {"filter", {{"type", "box"}, {"radius", 0.5}}}}},
            {"integrator", {{"type", integrator}, {"max_depth", 4}}},
            {"materials", {{"grey", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}},
                           {"lamp", {{"type", "emissive"}, {"radiance", {4, 4, 4}}, {"two_sided", false}}}}},
            {"objects", {{{"vertices", {-20, 0, -20, 20, 0, -20, 20, 0, 20, -20, 0, 20}}, {"indices", {0, 2, 1, 0, 3, 2}},
                          {"material", "grey"}},
                         {{"vertices", vertices}, {"indices", indices}, {"material", "lamp"}}}},
            {"lights", geometry::Json::array()}};
        auto loaded = loadSceneText(folder, scene.dump());
        EXPECT_EQ(loaded->lights.size(), size_t(sides));
        // Whitted samples each light once: the mesh there is one light.
        EXPECT_EQ(loaded->groupedLights.size(), 1u);
        const Image image = render(*loaded, {.threads = 2, .seed = 7, .quiet = true});
        const double expected = 0.5 / std::numbers::pi * polygonIrradiance(Vec3(0.3, 0, 0), Vec3(0, 1, 0), polygon, 4);
        EXPECT_NEAR(image.pixel(4, 4)[0], expected, 0.005 * expected) << integrator;
    }
}

// A 1 m^2 quad light and a disk of the same area at y = 3 face down onto a
// floor at y = -1. Floor points up to 30 m from the axis see them from 45 to
// 82 degrees off their normal; beyond 60 degrees a shadow ray that ends
// short of the light only when measured from the unshifted point reached
// past the light's plane and hit the light itself, so the floor went black.
// The closed form is Lambert's polygon formula (the disk is its 64-gon);
// NEE by area has little noise here, and 1,024 stratified paths keep it
// well under 1%.
TEST(DirectLighting, GrazingAreaLightsMatchThePolygonFormula) {
    const double radius = 1.0 / std::sqrt(std::numbers::pi);
    std::vector<Vec3> disk;
    for (int k = 0; k < 64; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / 64;
        // The disk light's own frame for the normal (0, -1, 0): a = -z, b = x.
        disk.push_back(Vec3(0, 3, 0) + radius * (std::cos(phi) * Vec3(0, 0, -1) + std::sin(phi) * Vec3(1, 0, 0)));
    }
    const std::vector<Vec3> quad{Vec3(-0.5, 3, -0.5), Vec3(0.5, 3, -0.5), Vec3(0.5, 3, 0.5), Vec3(-0.5, 3, 0.5)};
    const geometry::Json quadLight = {{"type", "quad"}, {"corner", {-0.5, 3, -0.5}}, {"edge1", {1, 0, 0}},
                                      {"edge2", {0, 0, 1}}, {"radiance", {25, 25, 25}}};
    const geometry::Json diskLight = {{"type", "disk"}, {"center", {0, 3, 0}}, {"normal", {0, -1, 0}},
                                      {"radius", radius}, {"radiance", {25, 25, 25}}};
    for (const char* integrator : {"path", "whitted"}) {
        for (const auto& [light, polygon] : {std::pair{quadLight, quad}, std::pair{diskLight, disk}}) {
            const geometry::Json& description = light;  // structured bindings cannot be captured before C++20 in clang 14
            const auto scene = floorScene(integrator, -1.0, [&](SceneBuilder& b) { b.addLight(description); });
            for (double x : {4.0, 8.0, 16.0, 22.7, 30.0}) {
                const double angle = std::atan2(x, 4.0) * 180 / std::numbers::pi;
                const double expected = 0.5 / std::numbers::pi * polygonIrradiance(Vec3(x, -1, 0), Vec3(0, 1, 0), polygon, 25);
                EXPECT_NEAR(radianceLookingDown(*scene, Vec3(x, 0, 0), 1024, 17), expected, 0.01 * expected)
                    << integrator << " " << light["type"] << " at " << x << " m, " << angle << " degrees off the light's normal";
            }
        }
    }
}
