// White furnaces of single BSDFs: the fraction of light a lossless material
// sends back out (reflected plus transmitted, radiance scaling undone), by
// roughness and incidence. Smooth materials keep all of it. Rough ones keep
// it too with multiple scattering (the default); with single scattering
// they lose the light that would bounce between facets, which grows with
// roughness and grazing angles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "renderer/material.h"
#include "renderer/microfacet.h"
#include "renderer/microfacet_albedo.h"

using namespace isotrace;

namespace {

Material make(const geometry::Json& description) {
    geometry::JsonObjectReader r(description, "", "furnace");
    Material m = materialRegistry().factoryFor(r)(r, MaterialContext{});
    r.finish();
    return m;
}

// Directional albedo at incidence theta: the mean sample weight (times
// eta^2 for refractions), and its standard error.
std::pair<double, double> directionalAlbedo(const BSDF& bsdf, double thetaDegrees, int samples = 200000,
                                            bool outside = true) {
    ShadingPoint p;
    p.geometricNormal = p.shadingNormal = Vec3(0, 0, 1);
    p.outside = outside;
    const double theta = thetaDegrees * std::numbers::pi / 180;
    const Vec3 wo(std::sin(theta), 0, std::cos(theta));
    Sampler sampler(SamplerType::Independent, 3);
    double sum = 0.0, sum2 = 0.0;
    for (int s = 0; s < samples; ++s) {
        sampler.startPixelSample(0, 0, s);
        const auto bs = bsdf.sample(p, wo, sampler);
        const double w = bs ? bs->weight.mean() * bs->etaRatio * bs->etaRatio : 0.0;
        sum += w;
        sum2 += w * w;
    }
    const double mean = sum / samples;
    return {mean, std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples)};
}

struct FurnaceCase {
    const char* name;
    geometry::Json description;  ///< without roughness
};


const FurnaceCase kLossless[] = {
    {"conductor", {{"type", "conductor"}, {"eta", {1, 1, 1}}, {"k", {1e4, 1e4, 1e4}}}},
    {"dielectric", {{"type", "dielectric"}, {"ior", 1.5}}},
    {"plastic", {{"type", "plastic"}, {"albedo", {1, 1, 1}}, {"ior", 1.5}}},
};

Material withRoughness(const FurnaceCase& c, double roughness, bool multipleScattering) {
    geometry::Json description = c.description;
    description["roughness"] = roughness;
    description["multiple_scattering"] = multipleScattering;
    return make(description);
}

}  // namespace

// The energy table of docs/scene-format.md: with multiple scattering every
// lossless material returns 1 within 2% (the tables' interpolation and
// the Fresnel colour model of Kulla and Conty), glass from either side.
TEST(WhiteFurnace, MultipleScatteringKeepsEveryLosslessMaterialWhite) {
    for (const FurnaceCase& c : kLossless) {
        for (const double roughness : {0.0, 0.3, 0.6, 1.0}) {
            const Material m = withRoughness(c, roughness, true);
            for (const bool outside : {true, false}) {
                if (!outside && !m.bsdf->transmits()) continue;
                for (const double theta : {0.0, 45.0, 75.0}) {
                    const auto [albedo, error] = directionalAlbedo(*m.bsdf, theta, 100000, outside);
                    std::printf("furnace %-10s %s roughness %.1f theta %2.0f: %.5f +- %.5f\n", c.name,
                                outside ? "outside" : "inside ", roughness, theta, albedo, error);
                    EXPECT_NEAR(albedo, 1.0, 0.02 + 4 * error)
                        << c.name << (outside ? " outside" : " inside") << " roughness " << roughness << " theta "
                        << theta;
                }
            }
        }
    }
}

// Single scattering, as pbrt has it: smooth materials within 5 standard
// errors of 1 (and never above), rough ones no more than the stated loss
// below 1, and the loss is there: the key turns compensation off.
TEST(WhiteFurnace, SingleScatteringLosesWhatFacetsBounce) {
    // Largest loss allowed at roughness 0.3 and 1 over 0-75 degrees: the
    // documented figures (measured 6.5% / 69%, 2.8% / 30%, 5.0% / 22%)
    // with a little margin. Roughness 1 is alpha 1, where half the visible
    // normals of a conductor seen head-on reflect below the horizon.
    const double allowedLoss[3][2] = {{0.08, 0.72}, {0.04, 0.32}, {0.06, 0.24}};
    for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) {
            const double roughness = r == 0 ? 0.0 : r == 1 ? 0.3 : 1.0;
            const Material m = withRoughness(kLossless[c], roughness, false);
            for (double theta : {0.0, 45.0, 75.0}) {
                const auto [albedo, error] = directionalAlbedo(*m.bsdf, theta);
                EXPECT_LT(albedo, 1.0 + 5 * error + 1e-9) << kLossless[c].name << " creates energy";
                if (r == 0) {
                    EXPECT_NEAR(albedo, 1.0, 5 * error + 1e-6) << kLossless[c].name << " smooth";
                } else {
                    EXPECT_GT(albedo, 1.0 - allowedLoss[c][r - 1]) << kLossless[c].name << " roughness "
                                                                    << roughness << " theta " << theta;
                }
                if (r == 2 && theta == 0.0) {
                    EXPECT_LT(albedo, 0.99) << kLossless[c].name << " lost nothing";
                }
            }
        }
    }
}

// The albedo tables against an independent estimate: the single-scattering
// BSDFs' own samples (random, not stratified), at table nodes and between
// them, within 4 standard errors and the interpolation error (1e-2 grazing,
// where E changes fastest in mu).
TEST(MicrofacetAlbedo, TablesAgreeWithTheSingleScatteringBsdfs) {
    const MicrofacetAlbedoTable& conductor = conductorAlbedo(0.0, 1.0);
    const auto dielectric = dielectricAlbedo(1.5, 0.0, 1.0);
    for (const double roughness : {0.3, 0.5, 0.6, 1.0}) {
        for (const double theta : {0.0, 30.0, 60.0, 75.0}) {
            const double mu = std::cos(theta * std::numbers::pi / 180);
            const double tolerance = theta > 70 ? 1e-2 : 4e-3;
            const auto [metal, metalError] =
                directionalAlbedo(*withRoughness(kLossless[0], roughness, false).bsdf, theta, 100000);
            EXPECT_NEAR(conductor.at(mu, roughness), metal, tolerance + 4 * metalError)
                << "conductor roughness " << roughness << " theta " << theta;
            const Material glass = withRoughness(kLossless[1], roughness, false);
            for (const bool outside : {true, false}) {
                const auto [total, error] = directionalAlbedo(*glass.bsdf, theta, 100000, outside);
                EXPECT_NEAR((outside ? dielectric->outside : dielectric->inside).at(mu, roughness), total,
                            tolerance + 4 * error)
                    << "dielectric roughness " << roughness << " theta " << theta << " outside " << outside;
            }
        }
    }
}
