#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/errors.h"
#include "renderer/image/image_output.h"
#include "renderer/scene_builder.h"
#include "support/chi_square.h"
#include "support/floor_scene.h"
#include "support/temporary_files.h"

using namespace isotrace;
using isotrace::testing::directionChiSquare;
using isotrace::testing::TemporaryFolder;

namespace {

// A width x 2width map, black but for texels where `bright(x, y)` holds.
std::string writeMap(const TemporaryFolder& folder, const std::string& name, int height, float value,
                     bool (*bright)(int, int, int)) {
    Image map;
    map.width = 2 * height;
    map.height = height;
    map.rgb.assign(size_t(map.width) * map.height * 3, 0.0f);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x)
            if (bright(x, y, height))
                for (int c = 0; c < 3; ++c) map.pixel(x, y)[c] = value;
    const std::string path = folder.file(name);
    writeImage(path, map, {}, false);
    return path;
}

// A floor at y = 0 under the environment.
std::unique_ptr<Scene> floorUnder(const geometry::Json& environment) {
    return isotrace::testing::floorScene("path", 0.0, [&](SceneBuilder& b) { b.addLight(environment); });
}

double floorRadiance(const Scene& scene, int samples) {
    return isotrace::testing::radianceLookingDown(scene, Vec3(0, 1, 0), samples, 9);
}

}  // namespace

// One bright block of texels, rows 4-7 and columns 20-35 of a 64x32 map:
// polar angles 22.5-45 degrees, azimuths 22.5-202.5 degrees. Its irradiance
// on a surface facing +y is L (phi1 - phi0) (sin^2 theta1 - sin^2 theta0) / 2.
// Bilinear lookups spread each edge over half a texel either way, which
// moves the integral by well under 1% here; 65,536 stratified samples of
// light and BSDF keep the noise below that.
TEST(EnvironmentMap, BrightBlockGivesItsClosedFormIrradiance) {
    TemporaryFolder folder;
    const std::string path = writeMap(folder, "block.exr", 32, 8.0f, [](int x, int y, int) {
        return y >= 4 && y < 8 && x >= 20 && x < 36;
    });
    const auto scene = floorUnder({{"type", "environment"}, {"file", path}});
    const double t0 = std::numbers::pi * 4 / 32, t1 = std::numbers::pi * 8 / 32;
    const double irradiance = 8.0 * (2 * std::numbers::pi * 16 / 64) * (std::pow(std::sin(t1), 2) - std::pow(std::sin(t0), 2)) / 2;
    const double expected = 0.5 / std::numbers::pi * irradiance;
    EXPECT_NEAR(floorRadiance(*scene, 65536), expected, 0.01 * expected);
}

// A sun cap at the zenith (the top 4 rows of a 512x256 map: within 2.8
// degrees) of radiance 2,000 over a sky of 0.5 and a black ground: the
// irradiance on a floor is pi (S sin^2 theta_c + L cos^2 theta_c). The
// bilinear ramp at the cap's edge is symmetric about it, where the cosine
// weight is close to linear: it moves the integral by far less than the
// tolerance. The cap's texels are those the old sampling, uniform in v
// within a texel, weighted by 1 / sin theta.
TEST(EnvironmentMap, SunCapAtTheZenithGivesItsClosedFormIrradiance) {
    TemporaryFolder folder;
    Image map;
    map.width = 512;
    map.height = 256;
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            const float v = y < 4 ? 2000.0f : y < 128 ? 0.5f : 0.0f;
            map.rgb.insert(map.rgb.end(), {v, v, v});
        }
    writeImage(folder.file("sun.exr"), map, {}, false);
    const auto scene = floorUnder({{"type", "environment"}, {"file", folder.file("sun.exr")}});
    const double capAngle = std::numbers::pi * 4 / 256;
    const double irradiance = std::numbers::pi * (2000.0 * std::pow(std::sin(capAngle), 2) +
                                                  0.5 * std::pow(std::cos(capAngle), 2));
    const double expected = 0.5 / std::numbers::pi * irradiance;
    EXPECT_NEAR(floorRadiance(*scene, 16384), expected, 0.005 * expected);
}

// A constant map and the constant environment light the floor alike (each
// converges to rho L; the map's samples follow its texels, not the cosine).
TEST(EnvironmentMap, ConstantMapMatchesTheConstantEnvironment) {
    TemporaryFolder folder;
    const std::string path = writeMap(folder, "grey.exr", 16, 0.7f, [](int, int, int) { return true; });
    const double fromMap = floorRadiance(*floorUnder({{"type", "environment"}, {"file", path}}), 16384);
    const double constant = floorRadiance(*floorUnder({{"type", "environment"}, {"radiance", {0.7, 0.7, 0.7}}}), 16384);
    EXPECT_NEAR(constant, 0.5 * 0.7, 1e-9);  // exact per sample (cosine sampling)
    EXPECT_NEAR(fromMap, constant, 0.005 * constant);
}

// The map's sampling routine against its density, for a map with a hot
// spot, a dark half and a gradient, turned about a slanted axis.
TEST(EnvironmentMap, SamplingPassesChiSquareAgainstItsPdf) {
    TemporaryFolder folder;
    Image map;
    map.width = 64;
    map.height = 32;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            const float v = x < 32 ? 0.0f : 0.2f + 0.05f * y + (std::abs(x - 48) < 3 && std::abs(y - 10) < 3 ? 20.0f : 0.0f);
            map.rgb.insert(map.rgb.end(), {v, 0.5f * v, 0.25f * v});
        }
    writeImage(folder.file("spot.exr"), map, {}, false);
    const auto scene = floorUnder({{"type", "environment"}, {"file", folder.file("spot.exr")}, {"scale", 2},
                                   {"rotate", {{"axis", {1, 1, 0}}, {"angle", 30}}}});
    const Light& env = *scene->lights[scene->environmentLight];
    Sampler sampler(SamplerType::Independent, 4);
    const int n = 400000;
    const auto result = directionChiSquare<Vec3>(
        n,
        [&](int i) {
            sampler.startPixelSample(i, 0, 0);
            const LightSample s = env.sample({}, sampler.get2D());
            if (s.pdf > 0) {
                EXPECT_NEAR(env.pdf({}, s.direction, {}, {}), s.pdf, 1e-6 * s.pdf);
            }
            return s.pdf > 0 ? s.direction : Vec3(Vec3::Zero());
        },
        [&](const Vec3& w) { return env.pdf({}, w, {}, {}); }, 20, 40, 24);
    EXPECT_EQ(result.impossible, 0.0);
    // The density jumps at texel edges, which cross the cells slantwise: the
    // expected counts integrate it on a 24x24 grid per cell. 1% level, Bonferroni-corrected over this file's two chi-square tests.
    EXPECT_GT(result.pValue, 0.01 / 2) << "chi2 " << result.statistic << " with " << result.degreesOfFreedom << " dof";
}

// The constant environment's cosine-weighted sampling from a surface.
TEST(EnvironmentLight, CosineSamplingPassesChiSquareAgainstItsPdf) {
    const auto scene = floorUnder({{"type", "environment"}, {"radiance", {1, 1, 1}}});
    const Light& env = *scene->lights[scene->environmentLight];
    const LightSampleContext context{Vec3::Zero(), Vec3(0.3, 0.8, -0.5).normalized()};
    Sampler sampler(SamplerType::Independent, 5);
    const auto result = directionChiSquare<Vec3>(
        200000,
        [&](int i) {
            sampler.startPixelSample(i, 1, 0);
            return env.sample(context, sampler.get2D()).direction;
        },
        [&](const Vec3& w) { return env.pdf(context, w, {}, {}); });
    EXPECT_EQ(result.impossible, 0.0);
    EXPECT_GT(result.pValue, 0.01 / 2) << "chi2 " << result.statistic << " with " << result.degreesOfFreedom << " dof";
}

TEST(EnvironmentMap, BadMapsAreErrorsNamingTheFile) {
    TemporaryFolder folder;
    auto error = [&](const geometry::Json& environment) {
        try {
            floorUnder(environment);
        } catch (const geometry::InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string missing = folder.file("nowhere.exr");
    EXPECT_NE(error({{"type", "environment"}, {"file", missing}}).find(missing), std::string::npos);
    Image square;
    square.width = square.height = 8;
    square.rgb.assign(8 * 8 * 3, 1.0f);
    writeImage(folder.file("square.exr"), square, {}, false);
    EXPECT_NE(error({{"type", "environment"}, {"file", folder.file("square.exr")}}).find("twice as wide"), std::string::npos);
    Image bad;
    bad.width = 8;
    bad.height = 4;
    bad.rgb.assign(8 * 4 * 3, 1.0f);
    bad.rgb[3 * 9 + 1] = -2.0f;
    writeImage(folder.file("negative.exr"), bad, {}, false);
    EXPECT_NE(error({{"type", "environment"}, {"file", folder.file("negative.exr")}}).find("texel (1, 1) is negative"),
              std::string::npos);
    bad.rgb[3 * 9 + 1] = std::nanf("");
    writeImage(folder.file("nan.exr"), bad, {}, false);
    EXPECT_NE(error({{"type", "environment"}, {"file", folder.file("nan.exr")}}).find("not finite"), std::string::npos);
    const std::string both = error({{"type", "environment"}, {"file", folder.file("square.exr")}, {"radiance", {1, 1, 1}}});
    EXPECT_NE(both.find("/radiance: give either"), std::string::npos) << both;
    EXPECT_NE(error({{"type", "environment"}, {"file", missing}, {"scale", -1}}).find("/scale"), std::string::npos);
    const std::string map = folder.file("square.exr");
    EXPECT_NE(error({{"type", "environment"}, {"file", map}, {"rotate", {{"axis", {0, 0, 0}}, {"angle", 10}}}})
                  .find("/rotate/axis: must not be the zero vector"),
              std::string::npos);
    EXPECT_NE(error({{"type", "environment"}, {"file", map}, {"rotate", {{"axis", {0, 1, 0}}}}}).find("/rotate"),
              std::string::npos);
    EXPECT_NE(error({{"type", "environment"}, {"file", map}, {"rotate", {{"axis", {0, 1, 0}}, {"angle", 10}, {"pivot", 1}}}})
                  .find("unknown key \"pivot\""),
              std::string::npos);
}
