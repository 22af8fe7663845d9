// First roots of polynomials isolated in the Bernstein basis, against roots
// put there by construction and against dense sampling of random ones.
#include <gtest/gtest.h>

#include <random>

#include "geometry/bernstein_root.h"

using namespace isotrace::geometry;

namespace {

// The degree-8 monomial coefficients of prod (u - r_k) times a positive
// quadratic for each pair of unused degrees.
Monomials<8> withRoots(const std::vector<double>& roots, double scale = 1.0) {
    Monomials<8> p{};
    p[0] = scale;
    int degree = 0;
    auto multiply = [&](double c0, double c1, double c2) {
        Monomials<8> q{};
        for (int k = 0; k <= degree; ++k) {
            q[k] += p[k] * c0;
            if (k + 1 <= 8) q[k + 1] += p[k] * c1;
            if (k + 2 <= 8) q[k + 2] += p[k] * c2;
        }
        p = q;
        degree += c2 != 0 ? 2 : 1;
    };
    for (double r : roots) multiply(-r, 1.0, 0.0);
    while (degree + 2 <= 8) multiply(1.0 + 0.1 * degree, 0.3, 1.0);  // no real roots: 0.09 < 4 (1 + ...)
    return p;
}

}  // namespace

TEST(BernsteinRoot, FindsTheFirstOfSeveralRoots) {
    const Monomials<8> p = withRoots({0.9, 0.3, 0.6});
    const auto first = firstBernsteinRoot<8>(p, 0.0, 1.0, 1e-9);
    ASSERT_TRUE(first);
    EXPECT_NEAR(*first, 0.3, 1e-9);
    const auto later = firstBernsteinRoot<8>(p, 0.35, 1.0, 1e-9);
    ASSERT_TRUE(later);
    EXPECT_NEAR(*later, 0.6, 1e-9);
    EXPECT_FALSE(firstBernsteinRoot<8>(p, 0.31, 0.59, 1e-9));
}

// A positive polynomial whose minimum is a hair above zero: the hulls must
// close in on it and prove it, not report a root.
TEST(BernsteinRoot, ProvesANearMissFree) {
    Monomials<8> p = withRoots({0.5, 0.5});
    p[0] += 1e-8;
    EXPECT_FALSE(firstBernsteinRoot<8>(p, 0.0, 1.0, 1e-12));
}

// Two roots closer than the tolerance (a thin sliver of surface, the
// polynomial dipping 2.5e-13 below zero between them): found.
TEST(BernsteinRoot, FindsRootsCloserThanTheTolerance) {
    const auto r = firstBernsteinRoot<8>(withRoots({0.4, 0.4 + 1e-6}), 0.0, 1.0, 1e-5);
    ASSERT_TRUE(r);
    EXPECT_NEAR(*r, 0.4, 1e-5);
}

// Random polynomials against the first sign change on a grid of 20,000 points.
TEST(BernsteinRoot, AgreesWithDenseSampling) {
    std::mt19937 rng(3);
    std::normal_distribution<double> n;
    int withRoot = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        Monomials<8> p;
        for (double& c : p) c = n(rng);
        constexpr int kSamples = 20000;
        double expected = -1;
        double previous = evaluatePolynomial<8>(p, 0.0);
        for (int i = 1; i <= kSamples && expected < 0; ++i) {
            const double u = double(i) / kSamples, v = evaluatePolynomial<8>(p, u);
            if ((v < 0) != (previous < 0)) expected = u;
            previous = v;
        }
        const auto got = firstBernsteinRoot<8>(p, 0.0, 1.0, 1e-10);
        if (expected < 0) {
            // No sign change seen: a root pair between samples is possible but
            // then the polynomial is tiny there.
            if (got) {
                EXPECT_LT(std::abs(evaluatePolynomial<8>(p, *got)), 1e-6) << "trial " << trial;
            }
            continue;
        }
        ++withRoot;
        ASSERT_TRUE(got) << "trial " << trial;
        EXPECT_LE(*got, expected + 1e-9) << "trial " << trial;
        EXPECT_NEAR(evaluatePolynomial<8>(p, *got), 0.0, 1e-8) << "trial " << trial;
        // No earlier sign change was skipped: at most a pair below the grid's spacing.
        EXPECT_GT(*got, expected - 1.0 / kSamples - 1e-9) << "trial " << trial;
    }
    EXPECT_GT(withRoot, 200);
}
