// The local models behind fast variational rendering: exact at their
// expansion point, within their stated value and gradient error everywhere
// in their box, with a sound gradient bound, on the hand fit whose weights
// (sum of |w| near 1e6 for values near 0.02) defeat termwise bounds of low
// order. Traced through them, the hand agrees with exact marching.
#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "geometry/mesh_file.h"
#include "geometry/variational/rbf_solver.h"
#include "geometry/tracing/implicit_surface.h"
#include "geometry/variational/patch_tracer.h"
#include "geometry/tracing/sphere_tracer.h"
#include "geometry/variational/variational_patch.h"
#include "support/embree_scene.h"
#include "support/same_hits.h"
#include "support/turned_placement.h"
#include "support/random_rays.h"

using namespace isotrace::geometry;

namespace {

const VariationalField& handField() {
    static const VariationalField field = [] {
        const auto points = orientedPointsOfMesh(readMeshFile(std::string(ISOTRACE_SOURCE_DIR) + "/scenes/meshes/hand.off"));
        return fitVariationalField(constraintsFromOrientedPoints(points, defaultNormalOffset(points), false));
    }();
    return field;
}

// A Hermite fit (value and exact gradient constraints) of every sixth
// vertex of the hand: terms 3 |d| (b.d) besides the r^3 ones.
const VariationalField& hermiteHandField() {
    static const VariationalField field = [] {
        const auto all = orientedPointsOfMesh(readMeshFile(std::string(ISOTRACE_SOURCE_DIR) + "/scenes/meshes/hand.off"));
        std::vector<OrientedPoint> points;
        for (size_t i = 0; i < all.size(); i += 6) points.push_back(all[i]);
        VariationalField f = fitVariationalField(constraintsFromOrientedPoints(points, defaultNormalOffset(points), true));
        EXPECT_FALSE(f.gradientCenters.empty());
        return f;
    }();
    return field;
}

// Boxes of the given edge centred on random constraint positions: where the
// surface is, and where centres lie inside the box (near terms).
std::vector<Box3> boxesOnTheSurface(const VariationalField& f, double edge, int count, std::mt19937& rng) {
    std::uniform_int_distribution<size_t> pick(0, f.centers.size() - 1);
    std::uniform_real_distribution<double> jitter(-0.5, 0.5);
    std::vector<Box3> boxes;
    for (int i = 0; i < count; ++i) {
        const Vec3 c = f.centers[pick(rng)] + edge * Vec3(jitter(rng), jitter(rng), jitter(rng));
        boxes.push_back(Box3::around(c, 0.5 * edge));
    }
    return boxes;
}

Vec3 randomPointIn(const Box3& box, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return box.lower + box.extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
}

}  // namespace

namespace {

void expectExactAtTheExpansionPoint(const VariationalField& f, std::vector<Box3> boxes) {
    for (const Box3& box : boxes) {
        const auto patch = buildVariationalPatch(f, box);
        ASSERT_TRUE(patch);
        Vec3 g, gp;
        const double v = f.valueAndGradient(box.center(), g);
        const double vp = patch->valueAndGradient(box.center(), gp);
        EXPECT_NEAR(vp, v, 1e-9);
        EXPECT_LT((gp - g).norm(), 1e-7);
        EXPECT_NEAR(patch->value(box.center()), v, 1e-9);
    }
}

// At random points of boxes on the surface, the model is within its stated
// value, gradient and Hessian errors of the field, the field's gradient
// within the model's bound, its value within the model's range and within
// the band around the model's plane.
void expectWithinStatedErrors(const VariationalField& f, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-1.0, 1.0);
    int checked = 0;
    for (double edge : {0.01, 0.02, 0.05}) {
        for (const Box3& box : boxesOnTheSurface(f, edge, 30, rng)) {
            const auto patch = buildVariationalPatch(f, box);
            ASSERT_TRUE(patch);
            // An anchor as the tracer makes one: e = f - model and its
            // gradient, known exactly at a point of the box.
            const Vec3 a = randomPointIn(box, rng);
            Vec3 ga, gpa;
            const double ea = f.valueAndGradient(a, ga) - patch->valueAndGradient(a, gpa);
            const Vec3 gradientEa = ga - gpa;
            for (int i = 0; i < 40; ++i) {
                // Corners, points within half the half-diagonal of the
                // centre (where the errors are told by the inner bound), and
                // anywhere in the box.
                const Vec3 inner = patch->expansionPoint +
                                   0.5 * box.halfDiagonal() * std::abs(jitter(rng)) *
                                       Vec3(jitter(rng), jitter(rng), jitter(rng)).normalized();
                const Vec3 x = i < 8 ? box.corner(i) : i < 16 ? inner : randomPointIn(box, rng);
                Vec3 g, gp;
                const double v = f.valueAndGradient(x, g);
                const double vp = patch->valueAndGradient(x, gp);
                ASSERT_LE(std::abs(vp - v), patch->valueError) << "edge " << edge;
                ASSERT_LE((gp - g).norm(), patch->gradientError) << "edge " << edge;
                // ... and within the errors told for its distance from the centre.
                const double reach = (x - patch->expansionPoint).norm();
                ASSERT_LE(std::abs(vp - v), patch->valueErrorWithin(reach)) << "edge " << edge;
                ASSERT_LE((gp - g).norm(), patch->gradientErrorWithin(reach)) << "edge " << edge;
                ASSERT_LE(g.norm(), patch->lipschitz) << "edge " << edge;
                ASSERT_TRUE(patch->range.contains(v)) << "edge " << edge;
                // Within the band around the model's plane (rays outside it skip the box).
                const double plane = patch->coefficients[0] + patch->planeSlope.dot(x - patch->expansionPoint);
                ASSERT_LE(std::abs(v - plane), patch->planeBand) << "edge " << edge;
                // The anchor's first- and second-order predictions of e.
                const double e = v - vp, distance = (x - a).norm();
                ASSERT_LE(std::abs(e - ea), patch->gradientError * distance + 2 * patch->evaluationNoise);
                ASSERT_LE(std::abs(e - ea - gradientEa.dot(x - a)),
                          0.5 * patch->hessianError * distance * distance + 2 * patch->evaluationNoise)
                    << "edge " << edge;
                // The slope along a direction is the model gradient's.
                const Vec3 u = Vec3(jitter(rng), jitter(rng), jitter(rng)).normalized();
                double slope;
                ASSERT_NEAR(patch->valueAndSlope(x, u, slope), vp, 4 * patch->evaluationNoise);
                ASSERT_NEAR(slope, gp.dot(u), patch->gradientNoise) << "edge " << edge;
                // The model's curvature along it, by a second difference
                // (inside the box, where the bound holds).
                const double step = 1e-2 * edge;
                const Vec3 y = box.center() + 0.9 * (x - box.center());
                const double second =
                    (patch->value(y + step * u) - 2 * patch->value(y) + patch->value(y - step * u)) / (step * step);
                ASSERT_LE(std::abs(second), patch->curvature + 8 * patch->evaluationNoise / (step * step))
                    << "edge " << edge;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 3 * 30 * 40);
}

}  // namespace

TEST(VariationalPatch, ExactAtTheExpansionPointWithTheExactGradient) {
    std::mt19937 rng(3);
    expectExactAtTheExpansionPoint(handField(), boxesOnTheSurface(handField(), 0.03, 20, rng));
}

TEST(VariationalPatch, StaysWithinItsStatedErrors) { expectWithinStatedErrors(handField(), 5); }

TEST(VariationalPatch, HermiteModelIsExactAtTheExpansionPoint) {
    const VariationalField& f = hermiteHandField();
    std::mt19937 rng(7);
    std::vector<Box3> boxes = boxesOnTheSurface(f, 0.03, 20, rng);
    // A gradient constraint's centre at the expansion point itself, where
    // the term is only once differentiable.
    boxes.push_back(Box3::around(f.gradientCenters[3], 0.02));
    expectExactAtTheExpansionPoint(f, boxes);
}

TEST(VariationalPatch, HermiteModelStaysWithinItsStatedErrors) { expectWithinStatedErrors(hermiteHandField(), 9); }

TEST(VariationalPatch, HermiteErrorShrinksWithTheBox) {
    const VariationalField& f = hermiteHandField();
    const Box3 big = Box3::around(f.centers[10], 0.02), small = Box3::around(f.centers[10], 0.01);
    const auto a = buildVariationalPatch(f, big), b = buildVariationalPatch(f, small);
    ASSERT_TRUE(a && b);
    EXPECT_LT(b->valueError, a->valueError / 8);
    EXPECT_FALSE(b->nearHermite.empty());
}

TEST(VariationalPatch, ErrorShrinksWithTheFifthPowerOfTheBox) {
    const VariationalField& f = handField();
    const Box3 big = Box3::around(f.centers[100], 0.01), small = Box3::around(f.centers[100], 0.005);
    const auto a = buildVariationalPatch(f, big), b = buildVariationalPatch(f, small);
    ASSERT_TRUE(a && b);
    // Halving the box divides s^5 by 32; the far sum weighs its nearest
    // terms by 1 / (r - s)^2, so it can grow a little.
    EXPECT_LT(b->valueError, a->valueError / 8);
    // Small enough to trace with (the hand's values are near 0.02 a
    // normal offset away): hits are refined exactly from within it.
    EXPECT_LT(b->valueError, 1e-3);
}

TEST(VariationalPatch, SingleHermiteTermAgreesFarAndNear) {
    // One term 3 |d| (b.d) (weight -b) seen from boxes at several distances:
    // far (in the polynomial), near (exact correction) and centred on it.
    VariationalField f;
    f.gradientCenters = {Vec3(0.3, -0.2, 0.1)};
    f.gradientWeights = {Vec3(0.5, -1.0, 2.0)};
    std::mt19937 rng(11);
    for (double away : {0.0, 0.05, 0.2, 1.0, 3.0}) {
        const Box3 box = Box3::around(f.gradientCenters[0] + away * Vec3(0.6, 0.8, 0.0), 0.1);
        const auto patch = buildVariationalPatch(f, box);
        ASSERT_TRUE(patch);
        EXPECT_EQ(patch->nearHermite.size(), away < 0.3 ? 1u : 0u) << away;
        for (int i = 0; i < 50; ++i) {
            const Vec3 x = i < 8 ? box.corner(i) : randomPointIn(box, rng);
            Vec3 g, gp;
            const double v = f.valueAndGradient(x, g), vp = patch->valueAndGradient(x, gp);
            ASSERT_LE(std::abs(vp - v), patch->valueError) << away;
            ASSERT_LE((gp - g).norm(), patch->gradientError + 1e-12) << away;
            ASSERT_LE(g.norm(), patch->lipschitz) << away;
            ASSERT_TRUE(patch->range.contains(v)) << away;
        }
    }
}

namespace {

// The hand traced through its models and by exact marching (the fields'
// general sphere tracer with its O(N) safe radius) must agree on every ray.
void expectSameHits(const FieldProgram& program, int rays) {
    isotrace::testing::expectSameHitsAsMarching(program, rays, rays / 5, 1, 0.9999);
}

}  // namespace

TEST(VariationalPatchTracing, ModelOnlyHitsLieWithinHalfAStepOfTheFirstRoot) {
    // Models of boxes the size of the accelerator's deepest ones, rays
    // through them at random: a hit the model proves alone must lie within
    // minStep / 2 of f's first root on the segment (found here by scanning
    // and bisecting exact values), with a normal within a thousandth of
    // f's gradient there.
    const VariationalField& f = handField();
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> jitter(-1.0, 1.0);
    const double minStep = 2e-6 * f.bounds().halfDiagonal();
    int hits = 0, modelHits = 0;
    for (const Box3& box : boxesOnTheSurface(f, 0.005, 60, rng)) {
        const auto patch = buildVariationalPatch(f, box);
        ASSERT_TRUE(patch);
        if (patch->holdsNoZero) continue;
        for (int i = 0; i < 30; ++i) {
            const Vec3 u = Vec3(jitter(rng), jitter(rng), jitter(rng)).normalized();
            const Vec3 origin = randomPointIn(box, rng) - 0.01 * u;
            double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
            if (!clipRayToBox(box, origin, u, t0, t1)) continue;
            const PatchTraceResult r = tracePatch(*patch, f, origin, u, t0, t1, minStep);
            ASSERT_TRUE(r.complete);
            if (!r.hit) continue;
            ++hits;
            if (!r.modelHit) continue;
            ++modelHits;
            EXPECT_EQ(r.exactEvaluations, 0);
            auto exact = [&](double t) { return f.value(origin + t * u); };
            constexpr int kSamples = 400;
            double a = t0, fa = exact(a), root = std::numeric_limits<double>::quiet_NaN();
            const double end = std::min(t1, r.t + minStep);
            for (int k = 1; k <= kSamples && std::isnan(root); ++k) {
                double b = t0 + (end - t0) * k / kSamples, fb = exact(b);
                if ((fa < 0) != (fb < 0)) {
                    for (int halving = 0; halving < 60 && b - a > 1e-4 * minStep; ++halving) {
                        const double m = 0.5 * (a + b), fm = exact(m);
                        ((fm < 0) == (fa < 0) ? a : b) = m;
                    }
                    root = 0.5 * (a + b);
                }
                a = b, fa = fb;
            }
            ASSERT_FALSE(std::isnan(root)) << "box " << box.center().transpose() << " ray " << i;
            ASSERT_LE(std::abs(r.t - root), 0.5 * minStep * 1.001) << "box " << box.center().transpose() << " ray " << i;
            Vec3 g;
            f.valueAndGradient(origin + root * u, g);
            EXPECT_LE((r.gradient - g).norm(), 1.01e-3 * g.norm());
        }
    }
    EXPECT_GE(hits, 300);
    // Most hits at this size need no exact sum (the test must exercise them).
    EXPECT_GE(modelHits, hits / 2);
}

TEST(VariationalPatchTracing, HandAgreesWithExactMarching) {
    FieldProgram program;
    program.addLeaf(VariationalLeafField{std::make_shared<VariationalField>(handField())});
    expectSameHits(program, 150);
}

TEST(VariationalPatchTracing, HermiteHandAgreesWithExactMarching) {
    FieldProgram program;
    program.addLeaf(VariationalLeafField{std::make_shared<VariationalField>(hermiteHandField())});
    expectSameHits(program, 150);
}

TEST(VariationalPatchTracing, HandAgreesWithExactMarchingOnGrazingRays) {
    // Rays along the surface, a hair off it: where the parabola steps, the
    // anchors ahead and the forced steps are tested hardest.
    for (const VariationalField* f : {&handField(), &hermiteHandField()}) {
        FieldProgram program;
        program.addLeaf(VariationalLeafField{std::make_shared<VariationalField>(*f)});
        isotrace::testing::expectSameHitsOnGrazingRays(program, 120, 20);
    }
}

TEST(VariationalPatchTracing, TransformedHandAgreesWithExactMarching) {
    // Twice the size, turned about a slanted axis: rays are traced in the
    // leaf's frame, gradients brought back.
    const LeafPlacement placement = isotrace::testing::turnedPlacement(0.7, Vec3(0.1, -0.2, 0.3), 2.0);
    FieldProgram program;
    program.addLeaf(VariationalLeafField{std::make_shared<VariationalField>(handField())}, placement);
    expectSameHits(program, 100);
}
