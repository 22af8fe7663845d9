// MPU implicits against what they are fitted to: the surface passes within
// the accuracy asked for of every input point, follows a sphere's radius
// between the points, is negative inside, and bad options are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/variational/constraints.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::testDataFile;

namespace {

std::vector<MpuPoint> load(const std::string& file) {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(testDataFile(file))) points.push_back({p.position, p.normal});
    return points;
}

double diagonalOf(const std::vector<MpuPoint>& points) {
    Box3 box;
    for (const MpuPoint& p : points) box.extend(p.position);
    return box.extent().norm();
}

// First-order distance of each input point to the fitted surface.
double worstDistance(const MpuField& f, const std::vector<MpuPoint>& points) {
    double worst = 0;
    for (const MpuPoint& p : points) {
        Vec3 g;
        worst = std::max(worst, std::abs(f.valueAndGradient(p.position, g)) / g.norm());
    }
    return worst;
}

}  // namespace

TEST(MpuField, PassesWithinTheAccuracyOfEveryPoint) {
    for (const char* file : {"sphere926.pwn", "oni.pwn"}) {
        const std::vector<MpuPoint> points = load(file);
        MpuOptions options;
        options.accuracy = 1e-3;
        MpuReport report;
        const MpuField f = MpuField::fit(points, options, &report);
        const double diagonal = diagonalOf(points);
        std::printf("%s: %zu points, %zu local functions (%zu general quadrics), depth %d, %.3f s, worst point %.2g of the diagonal\n",
                    file, points.size(), report.localFunctions, report.generalQuadrics, report.depth, report.seconds,
                    worstDistance(f, points) / diagonal);
        // Local fits meet the accuracy where the points are dense enough for
        // a cell's ball to hold 15 of them; blending neighbours that each
        // meet it stays within a small multiple of it (the sphere: 0.05x).
        // oni.pwn has 1,435 points for a figure with thin horns and fingers:
        // balls there must grow across features, and the worst point is 7x
        // the accuracy (the fit's report says so).
        const double allowed = std::string(file) == "oni.pwn" ? 10.0 : 3.0;
        EXPECT_LT(worstDistance(f, points), allowed * options.accuracy * diagonal) << file;
        for (const MpuPoint& p : points) {
            Vec3 g;
            f.valueAndGradient(p.position, g);
            ASSERT_GT(g.normalized().dot(p.normal), 0.5) << file << ": the gradient follows the normals";
        }
    }
}

// sphere926.pwn lies on a sphere: between the points too, the surface stays
// on it, inside is negative and outside positive.
TEST(MpuField, FollowsTheSphereItWasSampledFrom) {
    const std::vector<MpuPoint> points = load("sphere926.pwn");
    Box3 box;
    for (const MpuPoint& p : points) box.extend(p.position);
    const Vec3 center = box.center();
    const double radius = 0.5 * box.extent().mean();
    const MpuField f = MpuField::fit(points);
    EXPECT_LT(f.value(center), 0.0);
    std::mt19937 rng(4);
    std::normal_distribution<double> g;
    for (int i = 0; i < 500; ++i) {
        const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
        // The root along the ray from the centre, by bisection.
        double lo = 0.5 * radius, hi = 1.5 * radius;
        ASSERT_LT(f.value(center + lo * d), 0.0);
        ASSERT_GT(f.value(center + hi * d), 0.0);
        for (int k = 0; k < 50; ++k) {
            const double mid = 0.5 * (lo + hi);
            (f.value(center + mid * d) < 0 ? lo : hi) = mid;
        }
        EXPECT_NEAR(lo, radius, 0.01 * radius) << d.transpose();
    }
}

TEST(MpuField, BadInputIsRefused) {
    std::vector<MpuPoint> few(10, {Vec3(0, 0, 0), Vec3(0, 0, 1)});
    EXPECT_THROW(MpuField::fit(few), std::invalid_argument);
    std::vector<MpuPoint> same(40, {Vec3(1, 2, 3), Vec3(0, 0, 1)});
    EXPECT_THROW(MpuField::fit(same), std::invalid_argument);
    std::vector<MpuPoint> points = load("sphere926.pwn");
    MpuOptions bad;
    bad.support = 0.4;
    EXPECT_THROW(MpuField::fit(points, bad), std::invalid_argument);
    points[3].normal = Vec3(NAN, 0, 0);
    EXPECT_THROW(MpuField::fit(points), std::invalid_argument);
    auto error = [](const std::string& json) {
        try {
            FieldLibrary(Json::parse(json), "/fields", "scene.json").compile("m");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error(R"({"m": {"type": "mpu"}})").find("needs oriented points"), std::string::npos);
    EXPECT_NE(error(R"({"m": {"type": "mpu", "points": "missing.xyz"}})").find("/fields/m/points"), std::string::npos);
    EXPECT_NE(error(R"({"m": {"type": "mpu", "normals": [[0, 0, 0, 0, 0, 1]], "accuracy": 2}})").find("/fields/m/accuracy"),
              std::string::npos);
    EXPECT_NE(error(R"({"m": {"type": "mpu", "normals": [[0, 0, 0, 0, 0, 1]], "suport": 1}})").find("did you mean \"support\""),
              std::string::npos);
    EXPECT_NE(error(R"({"m": {"type": "mpu", "normals": [[0, 0, 0, 0, 0, 1]]}})").find("at least 15 points"), std::string::npos);
}
