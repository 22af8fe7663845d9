#include "geometry/tracing/sphere_tracer.h"

#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <unsupported/Eigen/Polynomials>

#include "geometry/tracing/implicit_surface.h"
#include "support/compile_field.h"
#include "support/embree_scene.h"
#include "support/field_catalog.h"
#include "support/random_rays.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;
using isotrace::testing::CatalogEntry;
using isotrace::testing::compileCatalogEntry;
using isotrace::testing::EmbreeScene;
using isotrace::testing::fieldCatalog;
using isotrace::testing::RandomRay;
using isotrace::testing::randomRayAt;

namespace {

std::optional<double> sphereHit(const Vec3& o, const Vec3& d, const Vec3& c, double r) {
    const Vec3 oc = o - c;
    const double a = d.dot(d), b = oc.dot(d), cc = oc.squaredNorm() - r * r;
    const double disc = b * b - a * cc;
    if (disc < 0) return std::nullopt;
    const double t = (-b - std::sqrt(disc)) / a;
    return t > 0 ? std::optional<double>(t) : std::nullopt;
}

// Entry and exit of a ray through an axis-aligned box (slabs).
std::optional<std::pair<double, double>> boxSpan(const Vec3& o, const Vec3& d, const Vec3& lo, const Vec3& hi) {
    double t0 = -INFINITY, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    if (t0 > t1) return std::nullopt;
    return std::make_pair(t0, t1);
}

// Smallest positive real root of the torus quartic
// (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + z^2) = 0 along a unit ray.
std::optional<double> torusHit(const Vec3& o, const Vec3& d, double R, double r) {
    const double b = 2 * o.dot(d), c = o.squaredNorm() + R * R - r * r;
    const double A = d.x() * d.x() + d.z() * d.z(), B = 2 * (o.x() * d.x() + o.z() * d.z()),
                 C = o.x() * o.x() + o.z() * o.z();
    Eigen::Matrix<double, 5, 1> coefficients;
    coefficients << c * c - 4 * R * R * C, 2 * b * c - 4 * R * R * B, b * b + 2 * c - 4 * R * R * A, 2 * b, 1.0;
    Eigen::PolynomialSolver<double, 4> solver(coefficients);
    std::optional<double> best;
    for (int i = 0; i < 4; ++i) {
        const auto root = solver.roots()[i];
        if (std::abs(root.imag()) > 1e-7 || root.real() <= 0) continue;
        // Polish the root with Newton steps on the quartic.
        double t = root.real();
        for (int k = 0; k < 5; ++k) {
            double f = 0, df = 0;
            for (int p = 4; p >= 0; --p) {
                df = df * t + f;
                f = f * t + coefficients[p];
            }
            if (df != 0) t -= f / df;
        }
        if (!best || t < *best) best = t;
    }
    return best;
}


void expectHitsMatch(const std::string& json, const std::function<std::optional<double>(const Vec3&, const Vec3&)>& truth) {
    ImplicitSurface surface(compileField(json));
    const double size = surface.bounds().extent().norm();
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        std::mt19937_64 rng(i);
        const RandomRay ray = randomRayAt(surface.bounds(), rng);
        const std::optional<double> expected = truth(ray.origin, ray.direction);
        const TraceResult r = surface.intersect(ray.origin, ray.direction, 0.0, INFINITY);
        ASSERT_EQ(r.hit, expected.has_value()) << "ray " << i << " o=" << ray.origin.transpose()
                                               << " d=" << ray.direction.transpose();
        if (expected) {
            ++hits;
            ASSERT_LE(std::abs(r.t - *expected), 1e-5 * size) << "ray " << i << " t=" << r.t << " expected " << *expected;
        }
    }
    EXPECT_GT(hits, 500);  // the test must exercise hits, not only misses
}

}  // namespace

TEST(SphereTracer, SphereHitDistanceMatchesClosedForm) {
    const Vec3 c(0.2, -0.1, 0.3);
    expectHitsMatch(R"({"type": "sphere", "center": [0.2, -0.1, 0.3], "radius": 0.9})",
                    [&](const Vec3& o, const Vec3& d) { return sphereHit(o, d, c, 0.9); });
}

TEST(SphereTracer, TorusHitDistanceMatchesQuarticRoots) {
    expectHitsMatch(R"({"type": "torus", "major": 1.0, "minor": 0.35})",
                    [](const Vec3& o, const Vec3& d) { return torusHit(o, d, 1.0, 0.35); });
}

TEST(SphereTracer, BoxHitDistanceMatchesSlabs) {
    const Vec3 lo(-0.6, -0.4, -0.8), hi(0.6, 0.4, 0.8);
    expectHitsMatch(R"({"type": "box", "size": [1.2, 0.8, 1.6]})", [&](const Vec3& o, const Vec3& d) {
        auto s = boxSpan(o, d, lo, hi);
        return s && s->first > 0 ? std::optional<double>(s->first) : std::nullopt;
    });
}

TEST(SphereTracer, CsgHitDistanceMatchesIntervalArithmeticOfSpans) {
    // Sphere minus box: the first point inside the sphere and outside the box.
    const Vec3 lo(-0.3, -0.3, -2.0), hi(0.3, 0.3, 2.0);
    expectHitsMatch(R"({"type": "difference", "of": [{"type": "sphere", "radius": 1},
                                                      {"type": "box", "size": [0.6, 0.6, 4]}]})",
                    [&](const Vec3& o, const Vec3& d) -> std::optional<double> {
                        const Vec3 oc = o;
                        const double b = oc.dot(d), c = oc.squaredNorm() - 1.0;
                        const double disc = b * b - c;
                        if (disc < 0) return std::nullopt;
                        const double t0 = -b - std::sqrt(disc), t1 = -b + std::sqrt(disc);
                        const auto box = boxSpan(o, d, lo, hi);
                        if (!box || box->second < t0 || box->first > t0) return t0;  // entry not inside the box
                        if (box->second < t1) return box->second;                   // leave the hole inside the sphere
                        return std::nullopt;
                    });
}

TEST(SphereTracer, RayStartingInsideFindsTheExit) {
    ImplicitSurface surface(compileField(R"({"type": "sphere", "radius": 1})"));
    const TraceResult r = surface.intersect(Vec3(0.2, 0, 0), Vec3(1, 0, 0), 0.0, INFINITY);
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.t, 0.8, 1e-6);
}

TEST(SphereTracer, RespectsTheRayInterval) {
    ImplicitSurface surface(compileField(R"({"type": "sphere", "radius": 1})"));
    EXPECT_FALSE(surface.intersect(Vec3(-3, 0, 0), Vec3(1, 0, 0), 0.0, 1.9).hit);
    const TraceResult far = surface.intersect(Vec3(-3, 0, 0), Vec3(1, 0, 0), 2.5, INFINITY);
    ASSERT_TRUE(far.hit);
    EXPECT_NEAR(far.t, 4.0, 1e-6);
}

// A relaxed step from the origin (1.6 x 1.95 = 3.12) would land past a
// small sphere at x = 2; the ball around its end (radius 1.07) does not meet
// the first ball, so the step must be refused and the small sphere found.
TEST(SphereTracer, OverRelaxedStepThatLeavesAGapIsRefused) {
    const FieldProgram field = compileField(
        R"({"type": "union", "of": [{"type": "sphere", "center": [2, 0, 0], "radius": 0.05},
                                    {"type": "sphere", "center": [6, 0, 0], "radius": 1}]})");
    TraceSettings settings;
    ASSERT_GT(settings.overRelaxation, 1.0);
    const TraceResult r = sphereTrace(field, 1.0, Vec3(0, 0, 0), Vec3(1, 0, 0), 0.0, 10.0, settings);
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.t, 1.95, 1e-6);
}

// Justified relaxed steps save evaluations where plain steps crawl: a ray
// meeting the plane y = 0 at a grazing angle (sin 0.1), where each plain
// step shrinks the distance by 10% and each relaxed one by 16%.
TEST(SphereTracer, OverRelaxationTakesFewerStepsAtGrazingAngles) {
    const FieldProgram field = compileField(R"({"type": "plane"})");
    TraceSettings plain, relaxed;
    plain.overRelaxation = 1.0;
    const Vec3 o(-10, 1, 0), d = Vec3(std::cos(0.1), -std::sin(0.1), 0);
    const TraceResult a = sphereTrace(field, 1.0, o, d, 0.0, 20.0, plain);
    const TraceResult b = sphereTrace(field, 1.0, o, d, 0.0, 20.0, relaxed);
    ASSERT_TRUE(a.hit);
    ASSERT_TRUE(b.hit);
    EXPECT_NEAR(b.t, a.t, 1e-6);
    EXPECT_NEAR(b.t, 1 / std::sin(0.1), 1e-6);
    EXPECT_LT(b.steps, 0.8 * a.steps);
}

// For every field type, the sphere tracer (through Embree) and the slow,
// robust interval-bisection reference agree on hit or miss and on the
// nearest hit, for 10,000 random rays.
class NoFalseMisses : public ::testing::TestWithParam<CatalogEntry> {};

TEST_P(NoFalseMisses, AgreesWithIntervalBisection) {
    ImplicitSurface surface(compileCatalogEntry(GetParam()));
    EmbreeScene scene;
    scene.attach(surface);
    scene.commit();
    const Box3 bounds = surface.bounds();
    const double size = bounds.extent().norm();
    TraceSettings reference;
    reference.epsilon = 1e-7 * size;
    int hits = 0;
    for (int i = 0; i < 10000; ++i) {
        std::mt19937_64 rng(100000 + i);
        const RandomRay ray = randomRayAt(bounds, rng);
        double tEnter = 0, tExit = INFINITY;
        TraceResult expected;
        if (clipRayToBox(bounds.expanded(1e-3 * size), ray.origin, ray.direction, tEnter, tExit))
            expected = intervalBisectionTrace(surface.field(), ray.origin, ray.direction, std::max(tEnter, 0.0), tExit,
                                              reference);
        const auto got = scene.intersect(ray.origin, ray.direction);
        ASSERT_EQ(got.hit, expected.hit) << GetParam().name << " ray " << i << " o=" << ray.origin.transpose()
                                         << " d=" << ray.direction.transpose() << " reference t=" << expected.t
                                         << " traced t=" << got.t;
        if (expected.hit) {
            ++hits;
            ASSERT_NEAR(got.t, expected.t, 1e-5 * size) << GetParam().name << " ray " << i;
        }
        // Occlusion queries stop at any proven root (TraceSettings::anyHit),
        // and only within the segment asked about: every fourth ray.
        if (i % 4 == 0) {
            ASSERT_EQ(scene.occluded(ray.origin, ray.direction, 1e30), expected.hit) << GetParam().name << " ray " << i;
            if (expected.hit) {
                ASSERT_FALSE(scene.occluded(ray.origin, ray.direction, expected.t - 1e-4 * size))
                    << GetParam().name << " ray " << i;
            }
        }
    }
    EXPECT_GT(hits, 100) << GetParam().name;
}

INSTANTIATE_TEST_SUITE_P(Catalog, NoFalseMisses, ::testing::ValuesIn(fieldCatalog()),
                         [](const auto& info) { return info.param.name; });
