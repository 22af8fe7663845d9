// Light through solids: rays that start inside implicit solids (CSG
// included) and closed meshes find their exit where geometry says, see the
// inside of the surface, and glass bends them by Snell's law; a glass
// sphere in a uniform environment is a white furnace in every pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "renderer/integrator.h"
#include "renderer/render.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::loadSceneText;
using isotrace::testing::TemporaryFolder;

namespace {

// First t > 0 where origin + t d meets the sphere (center c, radius r), or -1.
double sphereExit(const Vec3& origin, const Vec3& d, const Vec3& c, double r, bool fromInside) {
    const Vec3 o = origin - c;
    const double b = o.dot(d), disc = b * b - (o.squaredNorm() - r * r);
    if (disc < 0) return -1;
    const double t0 = -b - std::sqrt(disc), t1 = -b + std::sqrt(disc);
    if (fromInside) return t1;
    return t0 > 0 ? t0 : -1;
}

std::string solidsScene(const std::string& objects) {
    return R"({"camera": {"from": [0, 0, 5], "to": [0, 0, 0]},
      "materials": {"glass": {"type": "dielectric"}},
      "fields": {"ball": {"type": "sphere", "radius": 1},
                 "core": {"type": "sphere", "radius": 0.5},
                 "shell": {"type": "difference", "of": ["ball", "core"]},
                 "left": {"type": "sphere", "radius": 1, "center": [-0.5, 0, 0]},
                 "right": {"type": "sphere", "radius": 1, "center": [0.5, 0, 0]},
                 "lens": {"type": "intersection", "of": ["left", "right"]}},
      "objects": )" + objects + "}";
}

Vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<double> g;
    return Vec3(g(rng), g(rng), g(rng)).normalized();
}

// Checks rays from `count` points that `inside` accepts, in random
// directions, against `exit` (the analytic distance), and that the surface
// reports them as seen from inside.
template <class Inside, class Exit>
void expectExits(const Scene& scene, Inside&& inside, Exit&& exit, double tolerance, const char* what) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    int tested = 0;
    while (tested < 300) {
        const Vec3 origin(u(rng), u(rng), u(rng));
        if (!inside(origin)) continue;
        const Vec3 d = randomDirection(rng);
        SurfaceHit hit;
        ASSERT_TRUE(scene.intersect(Ray{origin, d}, INFINITY, hit)) << what << ": a ray from inside escaped";
        EXPECT_NEAR(hit.t, exit(origin, d), tolerance) << what << " from " << origin.transpose();
        const ShadingPoint p = shadingPointOf(scene, hit, -d);
        EXPECT_FALSE(p.outside) << what << ": the exit must be seen from inside";
        ++tested;
    }
}

}  // namespace

TEST(InsideRays, ImplicitSolidsFindTheExitAtTheAnalyticDistance) {
    TemporaryFolder folder;
    const double tolerance = 2e-5;  // single-precision Embree rays of length ~2
    {
        auto scene = loadSceneText(folder, solidsScene(R"([{"field": "ball", "material": "glass"}])"));
        expectExits(
            *scene, [](const Vec3& p) { return p.norm() < 0.99; },
            [](const Vec3& o, const Vec3& d) { return sphereExit(o, d, Vec3::Zero(), 1, true); }, tolerance, "sphere");
    }
    {
        // Inside a hollow ball's wall, the exit is the core when the ray meets it first.
        auto scene = loadSceneText(folder, solidsScene(R"([{"field": "shell", "material": "glass"}])"));
        expectExits(
            *scene, [](const Vec3& p) { return p.norm() > 0.51 && p.norm() < 0.99; },
            [](const Vec3& o, const Vec3& d) {
                const double core = sphereExit(o, d, Vec3::Zero(), 0.5, false);
                return core > 0 ? core : sphereExit(o, d, Vec3::Zero(), 1, true);
            },
            tolerance, "difference");
    }
    {
        // In a lens (two balls' intersection) the ray leaves through whichever ball it leaves first.
        auto scene = loadSceneText(folder, solidsScene(R"([{"field": "lens", "material": "glass"}])"));
        const Vec3 a(-0.5, 0, 0), b(0.5, 0, 0);
        expectExits(
            *scene, [&](const Vec3& p) { return (p - a).norm() < 0.99 && (p - b).norm() < 0.99; },
            [&](const Vec3& o, const Vec3& d) {
                return std::min(sphereExit(o, d, a, 1, true), sphereExit(o, d, b, 1, true));
            },
            tolerance, "intersection");
    }
}

// A closed mesh (a cube wound outwards): exits by the slab formula.
TEST(InsideRays, ClosedMeshesFindTheExitFromInside) {
    TemporaryFolder folder;
    const std::string cube = R"({"vertices": [-1,-1,-1, 1,-1,-1, 1,1,-1, -1,1,-1, -1,-1,1, 1,-1,1, 1,1,1, -1,1,1],
      "indices": [0,2,1, 0,3,2, 4,5,6, 4,6,7, 0,1,5, 0,5,4, 3,7,6, 3,6,2, 0,4,7, 0,7,3, 1,2,6, 1,6,5],
      "material": "glass"})";
    auto scene = loadSceneText(folder, solidsScene("[" + cube + "]"));
    expectExits(
        *scene, [](const Vec3& p) { return p.cwiseAbs().maxCoeff() < 0.99; },
        [](const Vec3& o, const Vec3& d) {
            double t = INFINITY;
            for (int axis = 0; axis < 3; ++axis)
                if (d[axis] != 0) t = std::min(t, ((d[axis] > 0 ? 1.0 : -1.0) - o[axis]) / d[axis]);
            return t;
        },
        2e-5, "cube mesh");
}

// A ray parallel to the axis at height h through a glass ball of index n:
// in the plane of incidence, it enters at angle i = asin(h), bends to
// r = asin(h / n), crosses a chord of length 2 cos(r), and leaves deviated by
// 2 (i - r). The renderer's intersector and BSDF must reproduce the path.
TEST(Glass, RaysThroughABallFollowSnellsLaw) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, solidsScene(R"([{"field": "ball", "material": "glass"}])"));
    const BSDF& glass = *scene->materials[scene->objects[0].material].bsdf;
    const double n = 1.5;
    for (double h : {0.0, 0.2, 0.5, 0.8, 0.95}) {
        const Vec3 start(0, h, 5), d(0, 0, -1);
        SurfaceHit entry;
        ASSERT_TRUE(scene->intersect(Ray{start, d}, INFINITY, entry));
        const double i = std::asin(h), r = std::asin(h / n);
        EXPECT_NEAR(entry.t, 5 - std::cos(i), 1e-5);
        ShadingPoint p = shadingPointOf(*scene, entry, -d);
        ASSERT_TRUE(p.outside);
        BSDFSample lobes[2];
        ASSERT_EQ(glass.deltaLobes(p, -d, lobes), 2);
        EXPECT_NEAR(lobes[0].weight[0], std::pow((n - 1) / (n + 1), 2), h == 0 ? 1e-12 : 1.0) << "normal incidence";
        const Vec3 inside = lobes[1].wi;
        SurfaceHit exit;
        ASSERT_TRUE(scene->intersect(Ray{offsetOrigin(entry.position, p.geometricNormal, inside), inside}, INFINITY, exit));
        EXPECT_NEAR((exit.position - entry.position).norm(), 2 * std::cos(r), 2e-4) << "chord at h " << h;
        p = shadingPointOf(*scene, exit, -inside);
        ASSERT_FALSE(p.outside);
        ASSERT_EQ(glass.deltaLobes(p, -inside, lobes), 2) << "no total internal reflection in a ball";
        const Vec3 out = lobes[1].wi;
        const double deviation = std::acos(std::clamp(out.dot(d), -1.0, 1.0));
        // The inner ray starts 1e-4 (1 + |p|) off the surface, which moves
        // its exit and so the exit normal by about that much.
        EXPECT_NEAR(deviation, 2 * (i - r), 5e-4) << "deviation at h " << h;
        // Entering scales radiance by 1 / n^2, leaving by n^2: the path keeps its weight.
        EXPECT_NEAR(lobes[1].etaRatio, 1 / n, 1e-15);
    }
}

// In a uniform environment of radiance 1, smooth glass (solid, as an
// implicit ball and as its mesh, or a thin sheet) keeps every path's weight
// at exactly 1 where the path escapes: every pixel is 1, not only the mean,
// at 16 spp. Paths still inside after max_depth bounces lose their share;
// in a ball that is below 1e-6.
TEST(Glass, UniformEnvironmentThroughGlassIsAWhiteFurnaceInEveryPixel) {
    TemporaryFolder folder;
    for (const char* objects : {R"([{"field": "ball", "material": "glass"}])",
                                R"([{"field": "ball", "as": "mesh", "resolution": 48, "material": "glass"}])",
                                R"([{"field": "ball", "material": "thin"}])"}) {
        std::string text = solidsScene(objects);
        text.replace(text.find(R"("glass": {"type": "dielectric"})"), 31,
                     R"("glass": {"type": "dielectric"}, "thin": {"type": "dielectric", "thin": true})");
        text.insert(text.rfind('}'), R"(, "lights": [{"type": "environment", "radiance": [1, 1, 1]}],
            "film": {"width": 24, "height": 24, "spp": 16}, "integrator": {"type": "path", "max_depth": 64, "rr_depth": 64})");
        auto scene = loadSceneText(folder, text);
        const Image image = render(*scene, {.threads = 2, .seed = 2, .quiet = true});
        double worst = 0.0;
        for (float v : image.rgb) worst = std::max(worst, std::abs(double(v) - 1.0));
        EXPECT_LT(worst, 1e-4) << objects;
    }
}

// The Whitted preview splits at glass instead of choosing: reflection and
// refraction branches together carry all the light, so a glass ball in a
// uniform environment is 1 in every pixel at one sample, less only the
// branches it drops (each of weight below 1e-3; near the rim, where
// reflection is strong, a pixel drops a few: 0.0028 at worst here) and
// those past max_depth. Choosing one lobe, or losing one, costs far more.
TEST(Glass, WhittedPreviewFollowsBothReflectionAndRefraction) {
    TemporaryFolder folder;
    std::string text = solidsScene(R"([{"field": "ball", "material": "glass"}])");
    text.insert(text.rfind('}'), R"(, "lights": [{"type": "environment", "radiance": [1, 1, 1]}],
        "film": {"width": 24, "height": 24, "spp": 1}, "integrator": {"type": "whitted", "max_depth": 16})");
    auto scene = loadSceneText(folder, text);
    const Image image = render(*scene, {.threads = 2, .seed = 2, .quiet = true});
    double worst = 0.0;
    for (float v : image.rgb) worst = std::max(worst, std::abs(double(v) - 1.0));
    EXPECT_LT(worst, 5e-3);
}
