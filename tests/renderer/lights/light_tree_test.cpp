// The light tree (renderer/light_tree.h) as pbrt-v4 and Mitsuba test their
// samplers: its choices against its own pmf (chi-square), pmfs that sum to
// one, no light that can light a point left unchosen, and direct
// irradiance that converges to the closed form at 1, 10 and 10^4 lights.
#include "renderer/light_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "renderer/light_sampler.h"
#include "renderer/object_lights.h"
#include "renderer/sampling/sampler.h"
#include "support/chi_square.h"
#include "support/floor_scene.h"
#include "support/polygon_irradiance.h"

using namespace isotrace;

namespace {

struct Quad {
    Vec3 corner, edge1, edge2;
    double radiance;
    std::vector<Vec3> polygon() const { return {corner, corner + edge1, corner + edge1 + edge2, corner + edge2}; }
};

// Small quads scattered over a 20 m square at heights 2 to 6, facing down
// (some tilted, some away from the floor when `tilted`), radiances spread
// over two decades.
std::vector<Quad> randomQuads(int count, uint32_t seed, bool tilted = false) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Quad> quads;
    for (int i = 0; i < count; ++i) {
        const Vec3 c(20 * u(rng) - 10, 2 + 4 * u(rng), 20 * u(rng) - 10);
        const double size = 0.05 + 0.3 * u(rng);
        Vec3 e1(size, 0, 0), e2(0, 0, size);  // e1 x e2 = -y: faces down
        if (tilted) {
            const Eigen::AngleAxisd turn(std::numbers::pi * u(rng), Vec3::Random().normalized());
            e1 = turn * e1, e2 = turn * e2;
        }
        quads.push_back({c, e1, e2, std::pow(10.0, 2 * u(rng))});
    }
    return quads;
}

// Quads as above, but level at height 4, one in each cell of a 1 m grid
// over 20 m x 15 m: none hides another from the floor, so their
// irradiances add up.
std::vector<Quad> levelQuads(uint32_t seed) {
    std::vector<Quad> quads = randomQuads(300, seed);
    for (int i = 0; i < 300; ++i) quads[size_t(i)].corner = Vec3(i % 20 - 10 + 0.2, 4, i / 20 - 7.5 + 0.2);
    return quads;
}

std::vector<std::unique_ptr<const Light>> areaLightsOf(const std::vector<Quad>& quads) {
    std::vector<std::unique_ptr<const Light>> lights;
    for (const Quad& q : quads) {
        Emission emission;
        emission.radiance = RGB::Constant(q.radiance);
        const Vec3 a = q.corner, b = a + q.edge1, c = b + q.edge2, d = a + q.edge2;
        lights.push_back(makeAreaLight({{a, b, c}, {a, c, d}}, emission));
    }
    return lights;
}

LightSampleContext randomContext(std::mt19937& rng, bool withNormal) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    LightSampleContext c{Vec3(24 * u(rng) - 12, 8 * u(rng) - 1, 24 * u(rng) - 12), Vec3::Zero()};
    if (withNormal) c.n = Vec3::Random().normalized();
    return c;
}

}  // namespace

TEST(LightTree, ChoosesEachLightAsItsPmfSays) {
    for (const int count : {10, 10000}) {
        const auto lights = areaLightsOf(randomQuads(count, 7, true));
        const LightSampler sampler(lights);
        ASSERT_EQ(sampler.tree().nodeCount(), size_t(2 * count - 1));
        EXPECT_LE(sampler.tree().depth(), 4 * int(std::log2(count)) + 1);
        std::mt19937 rng(3);
        for (int trial = 0; trial < 3; ++trial) {
            const LightSampleContext context = randomContext(rng, trial > 0);
            const double total = sampler.totalImportance(context);
            ASSERT_GT(total, 0.0);
            // The last cell counts the samples that find no light: a node may
            // be bright at the context while every light below it faces away.
            std::vector<double> expected(size_t(count) + 1, 0.0), observed(size_t(count) + 1, 0.0);
            double sum = 0.0;
            for (int i = 0; i < count; ++i) sum += expected[size_t(i)] = sampler.pmf(context, i, total);
            EXPECT_LE(sum, 1.0 + 1e-9);
            expected.back() = std::max(0.0, 1.0 - sum);
            const int samples = 20 * count;
            std::uniform_real_distribution<double> u(0.0, 1.0);
            for (int s = 0; s < samples; ++s) {
                double pmf = 0.0;
                const int chosen = sampler.sample(context, u(rng), total, pmf);
                if (chosen < 0) {
                    observed.back() += 1;
                    continue;
                }
                ASSERT_NEAR(pmf, expected[size_t(chosen)], 1e-12 * pmf);
                observed[size_t(chosen)] += 1;
            }
            for (double& e : expected) e *= samples;
            const isotrace::testing::ChiSquareResult r = isotrace::testing::chiSquareTest(observed, expected);
            EXPECT_EQ(r.impossible, 0.0);
            EXPECT_GT(r.pValue, 1e-4) << count << " lights, statistic " << r.statistic << " over "
                                      << r.degreesOfFreedom << " degrees of freedom";
        }
    }
}

// The tree's node bounds must not rule out a light that can light a point:
// that light would never be sampled, and its light lost.
TEST(LightTree, EveryLightThatCanLightAPointCanBeChosen) {
    auto lights = areaLightsOf(randomQuads(1000, 11, true));
    {
        // Two-sided emitters and implicit-like round emitters beside them.
        auto twoSided = randomQuads(100, 12, true);
        for (const Quad& q : twoSided) {
            Emission emission;
            emission.radiance = RGB::Constant(q.radiance);
            emission.twoSided = true;
            const Vec3 a = q.corner, b = a + q.edge1, c = b + q.edge2, d = a + q.edge2;
            lights.push_back(makeAreaLight({{a, b, c}, {a, c, d}}, emission));
        }
    }
    const LightSampler sampler(lights);
    std::mt19937 rng(5);
    int lit = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const LightSampleContext context = randomContext(rng, trial % 4 != 0);
        const double total = sampler.totalImportance(context);
        for (size_t i = 0; i < lights.size(); ++i) {
            // Whether the light reaches the context: one of 16 samples of it
            // does, above the context's horizon.
            bool reaches = false;
            for (int k = 0; k < 16 && !reaches; ++k) {
                const LightSample ls = lights[i]->sample(context, Eigen::Vector2d((k % 4 + 0.5) / 4, (k / 4 + 0.5) / 4));
                reaches = ls.pdf > 0 && ls.radiance.maxCoeff() > 0 && (context.n.isZero() || context.n.dot(ls.direction) > 0);
            }
            if (!reaches) continue;
            ++lit;
            ASSERT_GT(sampler.pmf(context, int(i), total), 0.0) << "light " << i << " at trial " << trial;
        }
    }
    EXPECT_GT(lit, 1000);
}

// Next-event estimation's own estimator, radiance cos / (pdf pmf), against
// Lambert's closed form for the sum of every quad's irradiance.
TEST(LightTree, DirectIrradianceIsUnbiased) {
    for (const int count : {1, 10, 10000}) {
        const std::vector<Quad> quads = randomQuads(count, 21);
        const auto lights = areaLightsOf(quads);
        const LightSampler sampler(lights);
        const LightSampleContext context{Vec3(0.3, 0, -0.2), Vec3(0, 1, 0)};
        double exact = 0.0;
        for (const Quad& q : quads) exact += isotrace::testing::polygonIrradiance(context.p, context.n, q.polygon(), q.radiance);
        const double total = sampler.totalImportance(context);
        Sampler random(SamplerType::Independent, 17);
        const int samples = 200000;
        double sum = 0.0, sumSquares = 0.0;
        for (int s = 0; s < samples; ++s) {
            random.startPixelSample(0, 0, s);
            double pmf = 0.0;
            double estimate = 0.0;
            if (const int chosen = sampler.sample(context, random.get1D(), total, pmf); chosen >= 0) {
                const LightSample ls = lights[size_t(chosen)]->sample(context, random.get2D());
                if (ls.pdf > 0) estimate = ls.radiance[1] * std::max(0.0, context.n.dot(ls.direction)) / (ls.pdf * pmf);
            }
            sum += estimate;
            sumSquares += estimate * estimate;
        }
        const double mean = sum / samples;
        const double standardError = std::sqrt(std::max(0.0, sumSquares / samples - mean * mean) / samples);
        EXPECT_NEAR(mean, exact, 4 * standardError + 1e-9 * exact) << count << " lights";
        EXPECT_LT(standardError, 0.05 * exact) << count << " lights";
    }
}

// The path integrator weighs light samples and BSDF samples that hit an
// emitter by the same pmf: a floor under many quads converges to the
// closed form with the tree as with the exhaustive walk.
TEST(LightTree, PathTracedFloorUnderManyQuadsMatchesTheClosedForm) {
    const std::vector<Quad> quads = levelQuads(31);
    const Vec3 at(0.5, 0, 0.25);
    double irradiance = 0.0;
    for (const Quad& q : quads) irradiance += isotrace::testing::polygonIrradiance(at, Vec3(0, 1, 0), q.polygon(), q.radiance);
    const double expected = 0.5 / std::numbers::pi * irradiance;
    for (const char* sampling : {"tree", "exhaustive"}) {
        const auto scene = isotrace::testing::floorScene(
            geometry::Json{{"type", "path"}, {"max_depth", 1}, {"light_sampler", sampling}}, 0.0, [&](SceneBuilder& b) {
                for (const Quad& q : quads)
                    b.addLight({{"type", "quad"},
                                {"corner", {q.corner.x(), q.corner.y(), q.corner.z()}},
                                {"edge1", {q.edge1.x(), q.edge1.y(), q.edge1.z()}},
                                {"edge2", {q.edge2.x(), q.edge2.y(), q.edge2.z()}},
                                {"radiance", {q.radiance, q.radiance, q.radiance}}});
            });
        EXPECT_EQ(scene->lightSampler.sampling(), std::string(sampling) == "tree" ? LightSampling::Tree
                                                                                 : LightSampling::Exhaustive);
        const double seen = isotrace::testing::radianceLookingDown(*scene, at + Vec3(0, 1, 0), 8192, 5);
        EXPECT_NEAR(seen, expected, 0.03 * expected) << sampling;
    }
}
