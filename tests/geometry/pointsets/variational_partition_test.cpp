// Partitioned variational fits: they interpolate every constraint as the
// dense fit does, follow it between constraints on a real model within the
// documented accuracy, keep signs where only zeros lie near, scale past the
// dense limit through the scene format, and refuse what the dense fit refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/mesh_file.h"
#include "geometry/pointsets/variational_partition.h"
#include "geometry/variational/rbf_solver.h"

using namespace isotrace::geometry;

namespace {

// Points on a torus (major 1, minor 0.35) with outward normals: a surface
// of genus 1 whose truth is known everywhere.
std::vector<OrientedPoint> torusPoints(int count) {
    std::vector<OrientedPoint> points;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> angle(0.0, 2 * M_PI);
    for (int i = 0; i < count; ++i) {
        const double u = angle(rng), v = angle(rng);
        const Vec3 ring(std::cos(u), 0, std::sin(u));
        const Vec3 n = std::cos(v) * ring + std::sin(v) * Vec3::UnitY();
        points.push_back({ring + 0.35 * n, n});
    }
    return points;
}

double torusDistance(const Vec3& p) {
    const double q = std::hypot(p.x(), p.z()) - 1.0;
    return std::hypot(q, p.y()) - 0.35;
}

// First-order distance of p to the zero set of an MPU field.
double surfaceDistance(const MpuField& f, const Vec3& p) {
    Vec3 g;
    const double v = f.valueAndGradient(p, g);
    return std::abs(v) / g.norm();
}

}  // namespace

TEST(VariationalPartition, InterpolatesEveryConstraint) {
    const std::vector<OrientedPoint> points = torusPoints(600);
    const ConstraintSet c = constraintsFromOrientedPoints(points, 0.02, false);
    PartitionReport report;
    PartitionOptions options;
    options.leafConstraints = 16;  // many balls, so most constraints lie in several
    const MpuField f = fitPartitionedVariationalField(c, &report, options);
    EXPECT_GT(report.locals, 20u);
    EXPECT_LT(report.largestLocal, c.values.size() / 2) << "the local fits are local";
    for (const ValueConstraint& v : c.values) ASSERT_NEAR(f.value(v.position), v.value, 1e-7) << v.position.transpose();
    EXPECT_LT(report.maxResidual, 1e-7);
    EXPECT_TRUE(report.warnings.empty());
    // Between the points it follows the torus (600 points: spacing ~0.1).
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> angle(0.0, 2 * M_PI);
    double worst = 0.0;
    for (int i = 0; i < 500; ++i) {
        const double u = angle(rng), v = angle(rng);
        const Vec3 ring(std::cos(u), 0, std::sin(u));
        worst = std::max(worst, surfaceDistance(f, ring + 0.35 * (std::cos(v) * ring + std::sin(v) * Vec3::UnitY())));
    }
    EXPECT_LT(worst, 0.01);
    // Inside the tube negative, in the hole and beyond positive.
    EXPECT_LT(f.value(Vec3(1, 0, 0)), 0.0);
    EXPECT_GT(f.value(Vec3(0, 0, 0)), 0.0);
    EXPECT_GT(f.value(Vec3(1.6, 0.3, 0)), 0.0);
}

// The hand (1,197 vertices, the dense fit's 2,398 unknowns): the surfaces
// of the two fits, compared at the mesh's face centres projected onto the
// dense one. Measured: mean 1.3e-4, max 5.1e-3 of the diagonal, the max at
// the wrist's large flat faces, where constraints lie far apart.
TEST(VariationalPartition, FollowsTheDenseFitOnTheHand) {
    IndexedMesh mesh = readMeshFile(std::string(ISOTRACE_SOURCE_DIR) + "/scenes/meshes/hand.off");
    weldCoincidentVertices(mesh);
    const std::vector<OrientedPoint> points = orientedPointsOfMesh(mesh);
    const ConstraintSet c = constraintsFromOrientedPoints(points, defaultNormalOffset(points), false);
    const VariationalField dense = fitVariationalField(c);
    const MpuField partition = fitPartitionedVariationalField(c);
    const double diagonal = c.bounds().extent().norm();
    double worst = 0.0, mean = 0.0;
    for (const auto& t : mesh.triangles) {
        Vec3 p = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
        for (int k = 0; k < 5; ++k) {
            Vec3 g;
            const double v = dense.valueAndGradient(p, g);
            p -= v / g.squaredNorm() * g;
        }
        const double d = surfaceDistance(partition, p) / diagonal;
        worst = std::max(worst, d);
        mean += d / double(mesh.triangles.size());
    }
    EXPECT_LT(mean, 3e-4);
    EXPECT_LT(worst, 1e-2);
}

// Only surface points and one interior point: balls far from the interior
// point hold zeros alone (f = 0 fits them: a surface everywhere) and must
// reach it.
TEST(VariationalPartition, BallsOfZerosReachASignedConstraint) {
    ConstraintSet c;
    for (const OrientedPoint& p : torusPoints(300)) c.addBoundary(p.position);
    c.addInterior(Vec3(1, 0, 0));
    c.addInterior(Vec3(-1, 0, 0));
    PartitionOptions options;
    options.leafConstraints = 8;
    options.ballConstraints = 16;
    const MpuField f = fitPartitionedVariationalField(c, nullptr, options);
    // The faint background term (weight 1e-6) pulls a value v by about 1e-6 |v|.
    for (const ValueConstraint& v : c.values) ASSERT_NEAR(f.value(v.position), v.value, 1e-7 + 1e-5 * std::abs(v.value));
    // Off the surface the field is not zero: every local took a sign. (Which
    // sign, far from both interior points, the local fits cannot know as the
    // global one does: partitioned fits want normal constraints.)
    EXPECT_GT(std::abs(f.value(Vec3(0, 0, 1))), 1e-3);
    EXPECT_GT(std::abs(f.value(Vec3(0, 0.2, -1))), 1e-3);
    EXPECT_LT(f.value(Vec3(0.9, 0.1, 0)), -1e-3);
    EXPECT_LT(f.value(Vec3(-1.1, -0.1, 0)), -1e-3);
}

TEST(VariationalPartition, RefusesWhatTheDenseFitRefuses) {
    auto error = [](const ConstraintSet& c) {
        try {
            fitPartitionedVariationalField(c);
        } catch (const FitError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    ConstraintSet zeros;
    for (const OrientedPoint& p : torusPoints(100)) zeros.addBoundary(p.position);
    EXPECT_NE(error(zeros).find("every constraint is zero"), std::string::npos);
    ConstraintSet twice = constraintsFromOrientedPoints(torusPoints(100), 0.02, false);
    twice.values.push_back(twice.values[7]);
    EXPECT_NE(error(twice).find("coincide"), std::string::npos);
    ConstraintSet flat;
    for (int i = 0; i < 200; ++i) flat.values.push_back({Vec3(std::cos(i), std::sin(1.7 * i), 0), i % 2 ? 1.0 : 0.0});
    EXPECT_NE(error(flat).find("one plane"), std::string::npos);
    ConstraintSet notFinite = constraintsFromOrientedPoints(torusPoints(100), 0.02, false);
    notFinite.values[3].value = NAN;
    EXPECT_NE(error(notFinite).find("not finite"), std::string::npos);
}

// Past the dense limit the scene format switches by itself: 12,000 points
// make 24,004 unknowns, which the dense solver refuses.
TEST(VariationalPartition, ScenesFitPastTheDenseLimit) {
    Json normals = Json::array();
    for (const OrientedPoint& p : torusPoints(12000))
        normals.push_back({p.position.x(), p.position.y(), p.position.z(), p.normal.x(), p.normal.y(), p.normal.z()});
    Json fields = {{"t", {{"type", "variational"}, {"normals", normals}, {"normal_offset", 0.02}}}};
    const FieldProgram f = FieldLibrary(fields, "/fields", "scene.json").compile("t");
    ASSERT_NE(f.singleLeaf(), nullptr);
    EXPECT_TRUE(std::holds_alternative<MpuLeafField>(f.singleLeaf()->shape));
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> angle(0.0, 2 * M_PI);
    for (int i = 0; i < 300; ++i) {
        const double u = angle(rng), v = angle(rng);
        const Vec3 ring(std::cos(u), 0, std::sin(u));
        const Vec3 n = std::cos(v) * ring + std::sin(v) * Vec3::UnitY();
        // The fitted field crosses zero within 1e-3 of the true surface.
        ASSERT_LT(f.value(ring + 0.349 * n), 0.0) << torusDistance(ring + 0.349 * n);
        ASSERT_GT(f.value(ring + 0.351 * n), 0.0);
    }
    // Forcing the dense solver names the limit.
    fields["t"]["solver"] = "dense";
    try {
        FieldLibrary(fields, "/fields", "scene.json").compile("t");
        ADD_FAILURE() << "the dense solver accepted 24,004 unknowns";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("above the limit of 20000 unknowns"), std::string::npos) << e.what();
    }
}

// Hermite constraints: at a constraint every interpolant reaching it has the
// same value and gradient, so the blend's gradient sum_i w_i grad f_i / W +
// sum_i (f_i - f) grad w_i / W is the constraint's exactly.
TEST(VariationalPartition, MeetsGradientConstraints) {
    const ConstraintSet c = constraintsFromOrientedPoints(torusPoints(400), 0.0, true);
    ASSERT_EQ(c.gradients.size(), 400u);
    PartitionOptions options;
    options.leafConstraints = 24;
    PartitionReport report;
    const MpuField f = fitPartitionedVariationalField(c, &report, options);
    EXPECT_GT(report.locals, 8u);
    for (const GradientConstraint& g : c.gradients) {
        Vec3 gradient;
        const double v = f.valueAndGradient(g.position, gradient);
        ASSERT_NEAR(v, 0.0, 1e-7);
        ASSERT_LT((gradient - g.gradient).norm(), 1e-5) << g.position.transpose();
    }
    EXPECT_LT(f.value(Vec3(1, 0, 0)), 0.0);
    EXPECT_GT(f.value(Vec3(0, 0, 0)), 0.0);
}
