// White furnaces of single BSDFs: the fraction of light a lossless material
// sends back out (reflected plus transmitted, radiance scaling undone), by
// roughness and incidence. Smooth materials keep all of it; rough ones lose
// what single-scattering microfacets lose (light that would bounce between
// facets), which grows with roughness and grazing angles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "renderer/material.h"

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
std::pair<double, double> directionalAlbedo(const BSDF& bsdf, double thetaDegrees, int samples = 200000) {
    ShadingPoint p;
    p.geometricNormal = p.shadingNormal = Vec3(0, 0, 1);
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

}  // namespace

// The energy table of docs/scene-format.md, and bounds on it: smooth
// materials within 5 standard errors of 1 (and never above), rough ones no
// more than the stated loss below 1.
TEST(WhiteFurnace, EachLosslessMaterialByRoughness) {
    const FurnaceCase cases[] = {
        {"conductor", {{"type", "conductor"}, {"eta", {1, 1, 1}}, {"k", {1e4, 1e4, 1e4}}}},
        {"dielectric", {{"type", "dielectric"}, {"ior", 1.5}}},
        {"plastic", {{"type", "plastic"}, {"albedo", {1, 1, 1}}, {"ior", 1.5}}},
    };
    // Largest loss allowed at roughness 0.3 and 1 over 0-75 degrees: the
    // documented figures (measured 6.5% / 69%, 2.8% / 30%, 5.0% / 22%)
    // with a little margin. Roughness 1 is alpha 1, where half the visible
    // normals of a conductor seen head-on reflect below the horizon.
    const double allowedLoss[3][2] = {{0.08, 0.72}, {0.04, 0.32}, {0.06, 0.24}};
    for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) {
            const double roughness = r == 0 ? 0.0 : r == 1 ? 0.3 : 1.0;
            geometry::Json description = cases[c].description;
            description["roughness"] = roughness;
            const Material m = make(description);
            for (double theta : {0.0, 45.0, 75.0}) {
                const auto [albedo, error] = directionalAlbedo(*m.bsdf, theta);
                std::printf("furnace %-10s roughness %.1f theta %2.0f: %.5f +- %.5f\n", cases[c].name, roughness, theta,
                            albedo, error);
                EXPECT_LT(albedo, 1.0 + 5 * error + 1e-9) << cases[c].name << " creates energy";
                if (r == 0) {
                    EXPECT_NEAR(albedo, 1.0, 5 * error + 1e-6) << cases[c].name << " smooth";
                } else {
                    EXPECT_GT(albedo, 1.0 - allowedLoss[c][r - 1]) << cases[c].name << " roughness " << roughness
                                                                     << " theta " << theta;
                }
            }
        }
    }
}
