// The microfacet distribution and Fresnel formulas against their
// mathematics: normalization, Smith's masking as the visible-normal
// integral, sampling against density, and Fresnel's closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "renderer/fresnel.h"
#include "renderer/microfacet.h"
#include "support/chi_square.h"

using namespace isotrace;

namespace {

// Integral of g over the unit sphere by a midpoint rule in (cos theta, phi).
template <class F>
double integrateSphere(F&& g, int n = 800) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            const double z = -1 + 2 * (i + 0.5) / n, phi = std::numbers::pi * (j + 0.5) / n;
            const double r = std::sqrt(1 - z * z);
            sum += g(Vec3(r * std::cos(phi), r * std::sin(phi), z));
        }
    return sum * (4 * std::numbers::pi) / (2.0 * n * n);
}

Vec3 direction(double thetaDegrees, double phiDegrees) {
    const double t = thetaDegrees * std::numbers::pi / 180, p = phiDegrees * std::numbers::pi / 180;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

}  // namespace

TEST(TrowbridgeReitz, ProjectedDensityIntegratesToOne) {
    for (double alpha : {0.2, 0.5, 1.0}) {
        const TrowbridgeReitz d(alpha, alpha);
        const double integral = integrateSphere([&](const Vec3& m) { return d.D(m) * m.z(); }, 1200);
        EXPECT_NEAR(integral, 1.0, 2e-3) << "alpha " << alpha;
    }
    const TrowbridgeReitz anisotropic(0.2, 0.6);
    EXPECT_NEAR(integrateSphere([&](const Vec3& m) { return m.z() > 0 ? anisotropic.D(m) * m.z() : 0.0; }, 1200), 1.0,
                2e-3);
}

// Smith's G1 is exactly what makes the visible normals a distribution:
// int G1(w) max(0, w.m) D(m) dm = cos(theta_w).
TEST(TrowbridgeReitz, VisibleNormalsIntegrateToOne) {
    for (double alpha : {0.2, 0.6, 1.0})
        for (double theta : {0.0, 30.0, 60.0, 85.0}) {
            const TrowbridgeReitz d(alpha, alpha);
            const Vec3 w = direction(theta, 20);
            EXPECT_NEAR(integrateSphere([&](const Vec3& m) { return d.visibleD(w, m); }, 1200), 1.0,
                        3e-3)
                << "alpha " << alpha << " theta " << theta;
        }
}

TEST(TrowbridgeReitz, VisibleNormalSamplingPassesChiSquare) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> uniform;
    // Alphas the 20 x 40 cells resolve (sharper lobes are tested through
    // the materials, whose chi-square bins are the same).
    for (double alpha : {0.25, 0.5, 1.0})
        for (double theta : {0.0, 45.0, 80.0}) {
            const TrowbridgeReitz d(alpha, alpha);
            const Vec3 w = direction(theta, 40);
            // The helper bins around +y: swap y and z (its own inverse).
            auto toY = [](const Vec3& v) { return Vec3(v.x(), v.z(), v.y()); };
            const auto result = isotrace::testing::directionChiSquare<Vec3>(
                100000, [&](int) { return toY(d.sampleVisibleNormal(w, {uniform(rng), uniform(rng)})); },
                [&](const Vec3& m) { return d.visibleD(w, toY(m)); }, 20, 40, 16);
            EXPECT_EQ(result.impossible, 0.0);
            EXPECT_GT(result.pValue, 0.01 / 9) << "alpha " << alpha << " theta " << theta << " chi2 " << result.statistic;
        }
}

TEST(Fresnel, DielectricMatchesClosedForms) {
    for (double eta : {1.33, 1.5, 2.42}) {
        EXPECT_NEAR(fresnelDielectric(1.0, eta), std::pow((eta - 1) / (eta + 1), 2), 1e-15);
        EXPECT_NEAR(fresnelDielectric(1.0, 1 / eta), std::pow((eta - 1) / (eta + 1), 2), 1e-15);
        EXPECT_NEAR(fresnelDielectric(1e-9, eta), 1.0, 1e-7) << "grazing incidence reflects everything";
        // Brewster's angle: the parallel polarization vanishes, leaving half
        // of the perpendicular reflectance, sin^2(theta_i - theta_t) / sin^2(theta_i + theta_t).
        const double thetaB = std::atan(eta), thetaT = std::asin(std::sin(thetaB) / eta);
        const double perpendicular = std::pow(std::sin(thetaB - thetaT) / std::sin(thetaB + thetaT), 2);
        EXPECT_NEAR(fresnelDielectric(std::cos(thetaB), eta), 0.5 * perpendicular, 1e-14);
        // Total internal reflection beyond the critical angle, from inside.
        const double critical = std::asin(1 / eta);
        EXPECT_EQ(fresnelDielectric(std::cos(critical + 1e-6), 1 / eta), 1.0);
        EXPECT_LT(fresnelDielectric(std::cos(critical - 1e-3), 1 / eta), 1.0);
        // Arriving from behind is the same as the inverse index from the front.
        EXPECT_NEAR(fresnelDielectric(-0.3, eta), fresnelDielectric(0.3, 1 / eta), 1e-15);
    }
}

TEST(Fresnel, ConductorMatchesClosedForms) {
    const RGB n(0.18299, 0.42108, 1.3734), k(3.4242, 2.3459, 1.7704);
    const RGB normal = fresnelConductor(1.0, n, k);
    for (int c = 0; c < 3; ++c) {
        const double expected = (std::pow(n[c] - 1, 2) + k[c] * k[c]) / (std::pow(n[c] + 1, 2) + k[c] * k[c]);
        EXPECT_NEAR(normal[c], expected, 1e-14);
    }
    EXPECT_GT(normal[0], normal[2]) << "gold reflects red more than blue";
    EXPECT_NEAR(fresnelConductor(1e-9, n, k).minCoeff(), 1.0, 1e-7);
    // Without absorption a conductor is a dielectric.
    for (double c : {1.0, 0.7, 0.3, 0.05})
        EXPECT_NEAR(fresnelConductor(c, RGB::Constant(1.5), RGB::Zero())[1], fresnelDielectric(c, 1.5), 1e-14);
}

TEST(Fresnel, DiffuseReflectanceObeysTheInsideOutsideRelation) {
    // Light conservation across an interface: eta^2 (1 - Fdr(1/eta)) = 1 - Fdr(eta).
    for (double eta : {1.2, 1.5, 2.0}) {
        const double outside = fresnelDiffuseReflectance(eta), inside = fresnelDiffuseReflectance(1 / eta);
        EXPECT_NEAR(eta * eta * (1 - inside), 1 - outside, 1e-5) << eta;
    }
    // The hemispherical average against a fine independent quadrature in theta.
    double sum = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double theta = (i + 0.5) / n * std::numbers::pi / 2;
        sum += fresnelDielectric(std::cos(theta), 1.5) * 2 * std::cos(theta) * std::sin(theta);
    }
    EXPECT_NEAR(fresnelDiffuseReflectance(1.5), sum * std::numbers::pi / 2 / n, 1e-6);
}

TEST(Fresnel, RefractionObeysSnell) {
    const Vec3 n(0, 0, 1);
    for (double theta : {0.0, 20.0, 50.0, 80.0}) {
        const Vec3 wi = direction(theta, 30);
        const auto t = refract(wi, n, 1.5);
        ASSERT_TRUE(t);
        EXPECT_NEAR(t->norm(), 1.0, 1e-14);
        const double sinT = std::sqrt(1 - t->z() * t->z());
        EXPECT_NEAR(sinT * 1.5, std::sin(theta * std::numbers::pi / 180), 1e-14);
        EXPECT_LT(t->z(), 0);
        EXPECT_NEAR(std::atan2(-t->y(), -t->x()), std::atan2(wi.y(), wi.x()), 1e-12) << "stays in the plane of incidence";
    }
    EXPECT_FALSE(refract(direction(60, 0), n, 1 / 1.5)) << "total internal reflection";
}
