// Variational implicit surfaces: the fit interpolates, signs are right,
// knots inserted on the surface change nothing, singular systems are
// named, and the field's bounds are sound.
#include <gtest/gtest.h>

#include <random>

#include "geometry/variational/rbf_solver.h"
#include "support/test_data.h"

using namespace isotrace::geometry;

namespace {

// Points spread over the unit sphere (a Fibonacci lattice) with outward normals.
std::vector<OrientedPoint> spherePoints(int count, double radius = 1.0) {
    std::vector<OrientedPoint> points;
    for (int i = 0; i < count; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1 - y * y), phi = 2.399963229728653 * i;
        const Vec3 n(r * std::cos(phi), y, r * std::sin(phi));
        points.push_back({radius * n, n});
    }
    return points;
}

}  // namespace

// Constraints all on one side (only "exterior" points) leave the field
// without a surface: the fit says so, once, and only then.
TEST(VariationalFit, WarnsWhenNoConstraintCanMakeASurface) {
    ConstraintSet outside;
    for (const OrientedPoint& p : spherePoints(20)) outside.addExterior(p.position);
    auto count = [](const FitReport& report, const std::string& text) {
        int n = 0;
        for (const std::string& w : report.warnings) n += w.find(text) != std::string::npos;
        return n;
    };
    FitReport report;
    fitVariationalField(outside, &report);
    EXPECT_EQ(count(report, "every constraint is exterior"), 1);
    ConstraintSet inside;
    for (const OrientedPoint& p : spherePoints(20)) inside.addInterior(p.position);
    fitVariationalField(inside, &report);
    EXPECT_EQ(count(report, "every constraint is interior"), 1);
}

TEST(VariationalFit, InterpolatesEveryConstraint) {
    const ConstraintSet set = constraintsFromOrientedPoints(spherePoints(200), 0.05, false);
    FitReport report;
    const VariationalField f = fitVariationalField(set, &report);
    for (const ValueConstraint& c : set.values) EXPECT_NEAR(f.value(c.position), c.value, 1e-9);
    EXPECT_LT(report.maxResidual, 1e-9);
    EXPECT_EQ(report.unknowns, 404u);
    EXPECT_TRUE(report.warnings.empty());
    // A sphere from its samples: inside at the centre, outside far away, and
    // the surface within 1% of the radius between samples.
    EXPECT_LT(f.value(Vec3::Zero()), 0.0);
    EXPECT_GT(f.value(Vec3(1.5, 0.2, 0)), 0.0);
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g;
    for (int i = 0; i < 100; ++i) {
        const Vec3 u = Vec3(g(rng), g(rng), g(rng)).normalized();
        EXPECT_LT(f.value(0.99 * u), 0.0);
        EXPECT_GT(f.value(1.01 * u), 0.0);
    }
}

TEST(VariationalFit, TetrahedronWithAnInteriorPointIsANearSphere) {
    // The 1999 paper's first figure: four boundary constraints at the
    // corners of a regular tetrahedron and one interior constraint at its
    // centre.
    ConstraintSet set;
    const Vec3 corners[4] = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
    for (const Vec3& c : corners) set.addBoundary(c);
    set.addInterior(Vec3::Zero());
    const VariationalField f = fitVariationalField(set);
    for (const Vec3& c : corners) EXPECT_NEAR(f.value(c), 0.0, 1e-12);
    EXPECT_NEAR(f.value(Vec3::Zero()), -1.0, 1e-12);
    // Near-spherical: the surface crosses each axis at about the same distance.
    auto crossing = [&](const Vec3& u) {
        double lo = 0, hi = 5;
        for (int i = 0; i < 100; ++i) (f.value(0.5 * (lo + hi) * u) < 0 ? lo : hi) = 0.5 * (lo + hi);
        return lo;
    };
    const double rx = crossing(Vec3(1, 0, 0)), ry = crossing(Vec3(0, 1, 0)), rc = crossing(Vec3(1, 1, 1).normalized());
    EXPECT_NEAR(rx, ry, 1e-9);           // tetrahedral symmetry
    EXPECT_NEAR(rx / rc, 1.0, 0.25);      // round, not a tetrahedron
}

TEST(VariationalFit, InteriorAndExteriorSignsAndTwoPointsInACube) {
    // The 1999 paper's ellipsoid-like figure: two boundary constraints inside
    // a cube of eight exterior constraints.
    ConstraintSet set;
    set.addBoundary(Vec3(-0.3, 0, 0));
    set.addBoundary(Vec3(0.3, 0, 0));
    for (int i = 0; i < 8; ++i) set.addExterior(Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    const VariationalField f = fitVariationalField(set);
    EXPECT_LT(f.value(Vec3::Zero()), 0.0);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(f.value(Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)), 1.0, 1e-12);
    EXPECT_GT(f.value(Vec3(0, 0.6, 0)), 0.0);
}

TEST(VariationalFit, KnotInsertedOnTheSurfaceChangesNothing) {
    const ConstraintSet set = constraintsFromOrientedPoints(spherePoints(60), 0.05, false);
    const VariationalField f = fitVariationalField(set);
    // A point where f is already zero: bisect along a ray between samples.
    const Vec3 u = Vec3(0.3, 0.5, 0.8).normalized();
    double lo = 0.5, hi = 1.5;
    for (int i = 0; i < 200; ++i) (f.value(0.5 * (lo + hi) * u) < 0 ? lo : hi) = 0.5 * (lo + hi);
    ConstraintSet more = set;
    more.addBoundary(lo * u);
    const VariationalField g = fitVariationalField(more);
    EXPECT_NEAR(g.weights.back(), 0.0, 1e-9 * std::abs(g.weights.front()));
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> coord(-1.5, 1.5);
    for (int i = 0; i < 200; ++i) {
        const Vec3 p(coord(rng), coord(rng), coord(rng));
        EXPECT_NEAR(g.value(p), f.value(p), 1e-8 * (1 + std::abs(f.value(p))));
    }
}

TEST(VariationalFit, HermiteConstraintsFixTheGradient) {
    const ConstraintSet set = constraintsFromOrientedPoints(spherePoints(80), 0.0, true);
    FitReport report;
    const VariationalField f = fitVariationalField(set, &report);
    EXPECT_EQ(report.unknowns, 80u + 3 * 80u + 4u);
    for (const GradientConstraint& c : set.gradients) {
        Vec3 g;
        EXPECT_NEAR(f.valueAndGradient(c.position, g), 0.0, 1e-9);
        EXPECT_LT((g - c.gradient).norm(), 1e-8);
    }
    EXPECT_LT(f.value(Vec3::Zero()), 0.0);
    EXPECT_GT(f.value(Vec3(0, 1.3, 0)), 0.0);
}

TEST(VariationalFit, SingularSystemsAreNamed) {
    auto message = [](const ConstraintSet& s, const FitOptions& o = {}) {
        try {
            fitVariationalField(s, nullptr, o);
        } catch (const FitError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    ConstraintSet coincident = constraintsFromOrientedPoints(spherePoints(20), 0.05, false);
    coincident.addExterior(coincident.values[6].position);
    EXPECT_NE(message(coincident).find("constraints 6 and 40 coincide"), std::string::npos) << message(coincident);

    ConstraintSet flat;
    for (int i = 0; i < 10; ++i) flat.values.push_back({Vec3(std::cos(i), std::sin(i), 0.5), i % 2 ? 1.0 : 0.0});
    EXPECT_NE(message(flat).find("lie in one plane"), std::string::npos) << message(flat);

    ConstraintSet zero;
    for (const auto& p : spherePoints(10)) zero.addBoundary(p.position);
    EXPECT_NE(message(zero).find("every constraint is zero"), std::string::npos) << message(zero);

    EXPECT_NE(message(ConstraintSet{}).find("no value constraints"), std::string::npos);

    const ConstraintSet big = constraintsFromOrientedPoints(spherePoints(100), 0.05, false);
    FitOptions small;
    small.maxUnknowns = 150;
    EXPECT_NE(message(big, small).find("204 unknowns need"), std::string::npos) << message(big, small);
}

TEST(VariationalFit, RangeAndLipschitzBoundsAreSound) {
    const VariationalField f = fitVariationalField(constraintsFromOrientedPoints(spherePoints(50), 0.05, false));
    const VariationalField h = fitVariationalField(constraintsFromOrientedPoints(spherePoints(30), 0.0, true));
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    for (const VariationalField* field : {&f, &h}) {
        for (int trial = 0; trial < 300; ++trial) {
            const double size = std::pow(10.0, -2.5 * u(rng));
            const Vec3 c(3 * u(rng) - 1.5, 3 * u(rng) - 1.5, 3 * u(rng) - 1.5);
            const Box3 box(c, c + Vec3(size * (0.2 + u(rng)), size * (0.2 + u(rng)), size * (0.2 + u(rng))));
            const Interval range = field->range(box);
            const double lipschitz = field->lipschitz(box);
            for (int i = 0; i < 20; ++i) {
                const Vec3 a = box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
                const Vec3 b = box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
                const double fa = field->value(a);
                ASSERT_TRUE(range.contains(fa)) << "trial " << trial;
                ASSERT_LE(std::abs(fa - field->value(b)), lipschitz * (a - b).norm() * (1 + 1e-9) + 1e-12);
            }
        }
    }
}

// Sphere tracing steps by the safe distance: no point within it may have
// the other sign.
TEST(VariationalFit, SafeDistanceHoldsNoZero) {
    const VariationalField f = fitVariationalField(constraintsFromOrientedPoints(spherePoints(60), 0.05, false));
    const VariationalField h = fitVariationalField(constraintsFromOrientedPoints(spherePoints(30), 0.0, true));
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> u(-1.6, 1.6);
    std::normal_distribution<double> g;
    for (const VariationalField* field : {&f, &h}) {
        int useful = 0;
        for (int trial = 0; trial < 300; ++trial) {
            const Vec3 x(u(rng), u(rng), u(rng));
            double safe = 0;
            const double fx = field->valueAndSafeDistance(x, safe);
            ASSERT_NEAR(fx, field->value(x), 1e-12 * (1 + std::abs(fx)));  // sums in another order
            ASSERT_GE(safe, 0.0);
            useful += safe > 0.01;
            for (int i = 0; i < 50; ++i) {
                const Vec3 y = x + safe * std::cbrt(std::abs(u(rng)) / 1.6) * Vec3(g(rng), g(rng), g(rng)).normalized();
                ASSERT_EQ(field->value(y) > 0, fx > 0) << "trial " << trial << " safe " << safe;
            }
        }
        EXPECT_GT(useful, 150) << "the radius is not uselessly small";
    }
}

TEST(VariationalFit, OrientedPointSetFromSharedData) {
    const std::vector<OrientedPoint> points = readOrientedPoints(isotrace::testing::testDataFile("sphere926.pwn"));
    ASSERT_EQ(points.size(), 926u);
    FitReport report;
    const VariationalField f =
        fitVariationalField(constraintsFromOrientedPoints(points, defaultNormalOffset(points), false), &report);
    EXPECT_EQ(report.unknowns, 2 * 926u + 4);
    EXPECT_LT(report.maxResidual, 1e-7);
    Box3 box;
    for (const auto& p : points) box.extend(p.position);
    EXPECT_LT(f.value(box.center()), 0.0);
    EXPECT_GT(f.value(box.upper + box.extent()), 0.0);
}
