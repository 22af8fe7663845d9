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

TEST(VariationalPatch, ExactAtTheExpansionPointWithTheExactGradient) {
    const VariationalField& f = handField();
    std::mt19937 rng(3);
    for (const Box3& box : boxesOnTheSurface(f, 0.03, 20, rng)) {
        const auto patch = buildVariationalPatch(f, box);
        ASSERT_TRUE(patch);
        Vec3 g, gp;
        const double v = f.valueAndGradient(box.center(), g);
        const double vp = patch->valueAndGradient(box.center(), gp);
        EXPECT_NEAR(vp, v, 1e-9);
        EXPECT_LT((gp - g).norm(), 1e-7);
    }
}

TEST(VariationalPatch, StaysWithinItsStatedErrors) {
    const VariationalField& f = handField();
    std::mt19937 rng(5);
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
                const Vec3 x = i < 8 ? box.corner(i) : randomPointIn(box, rng);
                Vec3 g, gp;
                const double v = f.valueAndGradient(x, g);
                const double vp = patch->valueAndGradient(x, gp);
                ASSERT_LE(std::abs(vp - v), patch->valueError) << "edge " << edge;
                ASSERT_LE((gp - g).norm(), patch->gradientError) << "edge " << edge;
                ASSERT_LE(g.norm(), patch->lipschitz) << "edge " << edge;
                ASSERT_TRUE(patch->range.contains(v)) << "edge " << edge;
                // The anchor's first- and second-order predictions of e.
                const double e = v - vp, distance = (x - a).norm();
                ASSERT_LE(std::abs(e - ea), patch->gradientError * distance + 2 * patch->evaluationNoise);
                ASSERT_LE(std::abs(e - ea - gradientEa.dot(x - a)),
                          0.5 * patch->hessianError * distance * distance + 2 * patch->evaluationNoise)
                    << "edge " << edge;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 3 * 30 * 40);
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

TEST(VariationalPatch, HermiteFieldsHaveNone) {
    VariationalField f;
    f.centers = {Vec3(0, 0, 0)};
    f.weights = {1.0};
    f.gradientCenters = {Vec3(1, 0, 0)};
    f.gradientWeights = {Vec3(0, 1, 0)};
    EXPECT_FALSE(buildVariationalPatch(f, Box3::around(Vec3(0, 0, 0), 1)));
}

namespace {

// The hand traced through its models and by exact marching (the fields'
// general sphere tracer with its O(N) safe radius) must agree on every ray.
void expectSameHits(const FieldProgram& program, int rays) {
    isotrace::testing::expectSameHitsAsMarching(program, rays, rays / 5, 1, 0.9999);
}

}  // namespace

TEST(VariationalPatchTracing, HandAgreesWithExactMarching) {
    FieldProgram program;
    program.addLeaf(VariationalLeafField{std::make_shared<VariationalField>(handField())});
    expectSameHits(program, 150);
}

TEST(VariationalPatchTracing, TransformedHandAgreesWithExactMarching) {
    // Twice the size, turned about a slanted axis: rays are traced in the
    // leaf's frame, gradients brought back.
    const LeafPlacement placement = isotrace::testing::turnedPlacement(0.7, Vec3(0.1, -0.2, 0.3), 2.0);
    FieldProgram program;
    program.addLeaf(VariationalLeafField{std::make_shared<VariationalField>(handField())}, placement);
    expectSameHits(program, 100);
}
