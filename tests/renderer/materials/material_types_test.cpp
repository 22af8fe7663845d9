#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "renderer/light.h"
#include "renderer/material.h"
#include "renderer/scene_builder.h"
#include "support/chi_square.h"
#include "support/plugin_catalog.h"

using namespace isotrace;
using isotrace::testing::lightCatalog;
using isotrace::testing::materialCatalog;
using isotrace::testing::missingFrom;
using isotrace::testing::PluginEntry;

TEST(PluginCatalog, CoversEveryRegisteredMaterialAndLightType) {
    EXPECT_EQ(missingFrom(materialCatalog(), materialRegistry().names()), std::vector<std::string>{})
        << "add the new material type to tests/support/plugin_catalog.h";
    EXPECT_EQ(missingFrom(lightCatalog(), lightRegistry().names()), std::vector<std::string>{})
        << "add the new light type to tests/support/plugin_catalog.h";
}

namespace {

Material make(const PluginEntry& entry) {
    geometry::JsonObjectReader r(entry.description, "", "catalog");
    Material m = materialRegistry().factoryFor(r)(r);
    r.finish();
    return m;
}

// A shading point with a tilted normal, so nothing leans on axis alignment.
ShadingPoint tiltedPoint() {
    ShadingPoint p;
    p.position = Vec3(0.1, 0.2, 0.3);
    p.geometricNormal = p.shadingNormal = Vec3(0.3, 1.0, -0.2).normalized();
    return p;
}

Vec3 directionAbove(const Vec3& n, std::mt19937& rng) {
    std::normal_distribution<double> g;
    Vec3 v(g(rng), g(rng), g(rng));
    v.normalize();
    return v.dot(n) < 0 ? Vec3(-v) : v;
}

}  // namespace

class EveryMaterial : public ::testing::TestWithParam<PluginEntry> {};

// What the integrators rely on of every BSDF: a sample's weight and pdf are
// f cos / pdf and pdf(wi); f is reciprocal; delta lobes are invisible to
// evaluate() and pdf(); and the reflected energy (estimated by sampling) is
// the stated albedo, at most 1.
TEST_P(EveryMaterial, SamplesAgreeWithEvaluateAndPdf) {
    const Material m = make(GetParam());
    if (!m.bsdf) {
        EXPECT_TRUE(m.isEmissive()) << "a material with neither BSDF nor emission";
        return;
    }
    const BSDF& bsdf = *m.bsdf;
    const ShadingPoint p = tiltedPoint();
    const Vec3& n = p.shadingNormal;
    std::mt19937 rng(7);
    Sampler sampler(SamplerType::Independent, 11);
    for (int trial = 0; trial < 20; ++trial) {
        const Vec3 wo = directionAbove(n, rng), wi = directionAbove(n, rng);
        EXPECT_TRUE((bsdf.evaluate(p, wo, wi) - bsdf.evaluate(p, wi, wo)).abs().maxCoeff() < 1e-12) << "reciprocity";
        RGB sum = RGB::Zero();
        const int samples = 4000;
        for (int s = 0; s < samples; ++s) {
            sampler.startPixelSample(trial, s, 0);
            const std::optional<BSDFSample> bs = bsdf.sample(p, wo, sampler);
            if (!bs) continue;
            sum += bs->weight;
            if (bs->delta) {
                EXPECT_EQ(bsdf.pdf(p, wo, bs->wi), 0.0);
                EXPECT_TRUE((bsdf.evaluate(p, wo, bs->wi) == 0).all());
                continue;
            }
            const double cosTheta = std::abs(n.dot(bs->wi));
            ASSERT_NEAR(bs->pdf, bsdf.pdf(p, wo, bs->wi), 1e-12 * bs->pdf);
            const RGB expected = bsdf.evaluate(p, wo, bs->wi) * cosTheta / bs->pdf;
            ASSERT_TRUE(((bs->weight - expected).abs() <= 1e-12 * (1 + expected.abs())).all());
        }
        const RGB energy = sum / samples;
        EXPECT_TRUE((energy <= 1.0 + 1e-9).all()) << energy.transpose();
        // Each sample's weight is bounded by 1 here, so the mean's standard
        // error is below 0.5 / sqrt(4000) = 0.008.
        EXPECT_TRUE(((energy - bsdf.albedo(p)).abs() < 0.03).all()) << energy.transpose() << " vs "
                                                                   << bsdf.albedo(p).transpose();
    }
}

// Every non-delta BSDF's sample() against its pdf() (Pearson's chi-square
// over cells of equal solid angle), for several incident directions: the
// 1% level after a Bonferroni correction over materials and directions.
TEST_P(EveryMaterial, SamplingPassesChiSquareAgainstPdf) {
    const Material m = make(GetParam());
    if (!m.bsdf || m.bsdf->isDeltaOnly()) GTEST_SKIP() << "no lobe with a density";
    const ShadingPoint p = tiltedPoint();
    std::mt19937 rng(3);
    const int directions = 4;
    const double level = 0.01 / (directions * double(materialCatalog().size()));
    for (int k = 0; k < directions; ++k) {
        const Vec3 wo = directionAbove(p.shadingNormal, rng);
        Sampler sampler(SamplerType::Independent, 100 + k);
        const auto result = isotrace::testing::directionChiSquare<Vec3>(
            100000,
            [&](int i) {
                sampler.startPixelSample(i, k, 0);
                const auto s = m.bsdf->sample(p, wo, sampler);
                return s ? s->wi : Vec3(Vec3::Zero());
            },
            [&](const Vec3& w) { return m.bsdf->pdf(p, wo, w); });
        EXPECT_EQ(result.impossible, 0.0);
        EXPECT_GT(result.pValue, level) << "chi2 " << result.statistic << ", " << result.degreesOfFreedom << " dof";
    }
}

INSTANTIATE_TEST_SUITE_P(Catalog, EveryMaterial, ::testing::ValuesIn(materialCatalog()),
                         [](const auto& info) { return info.param.name; });

class EveryLight : public ::testing::TestWithParam<PluginEntry> {};

// A light's samples carry the density pdf() gives for the point they chose,
// and a light that sends light to a point has importance there.
TEST_P(EveryLight, SamplesAgreeWithPdf) {
    SceneBuilder builder;
    builder.addLight(GetParam().description);
    const std::unique_ptr<Scene> scene = builder.build();
    ASSERT_EQ(scene->lights.size(), 1u);
    const Light& light = *scene->lights[0];
    const Vec3 p(0.1, 0, 0.2);
    Sampler sampler(SamplerType::Sobol, 5);
    for (int s = 0; s < 128; ++s) {
        sampler.startPixelSample(0, 0, s);
        // From a point in space, and from a surface facing up.
        const LightSampleContext context{p, s % 2 ? Vec3(0, 1, 0) : Vec3::Zero()};
        const LightSample ls = light.sample(context, sampler.get2D());
        ASSERT_NEAR(ls.direction.norm(), 1.0, 1e-12);
        // A light that can light the point must have a chance to be chosen.
        const bool contributes = (ls.radiance > 0).any() && ls.pdf > 0 && (context.n.isZero() || context.n.dot(ls.direction) > 0);
        if (contributes) EXPECT_GT(light.importance(context), 0.0) << "sample " << s;
        EXPECT_EQ(ls.isDelta, light.isDelta());
        if (light.isDelta()) continue;
        const Vec3 onLight = std::isfinite(ls.distance) ? ls.point : ls.direction;
        if (std::isfinite(ls.distance)) EXPECT_LT((ls.point - (p + ls.distance * ls.direction)).norm(), 1e-9);
        // Area lights in the catalog face down at y = 2: their normal is -y.
        EXPECT_NEAR(light.pdf(context, ls.direction, onLight, Vec3(0, -1, 0)), ls.pdf, 1e-9 * ls.pdf);
        EXPECT_GT(ls.radiance.maxCoeff(), 0.0);
    }
}

INSTANTIATE_TEST_SUITE_P(Catalog, EveryLight, ::testing::ValuesIn(lightCatalog()),
                         [](const auto& info) { return info.param.name; });
