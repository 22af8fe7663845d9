// MPU implicits against what they are fitted to: the surface passes within
// the accuracy asked for of every input point, follows a sphere's radius
// between the points, is negative inside, and bad options are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/variational/constraints.h"
#include "support/drilled_cube.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::testDataFile;

namespace {

std::vector<MpuPoint> loadPath(const std::string& path) {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(path)) points.push_back({p.position, p.normal});
    return points;
}

std::vector<MpuPoint> load(const std::string& file) { return loadPath(testDataFile(file)); }

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
        // balls there must grow across features, and the worst point is 3.1x
        // the accuracy. It was 5.6x while grown balls kept their support over
        // points their functions miss by far.
        const bool sparse = std::string(file) == "oni.pwn";
        const double allowed = sparse ? 4.0 : 3.0;
        EXPECT_LT(worstDistance(f, points), allowed * options.accuracy * diagonal) << file;
        // The gradient follows the normals: never against one, and within
        // 26 degrees almost everywhere. On oni's thin parts the fit puts
        // creases (max or min of two sides) where the points' normals jump,
        // and a point on a crease takes one side's gradient.
        size_t turned = 0;
        for (const MpuPoint& p : points) {
            Vec3 g;
            f.valueAndGradient(p.position, g);
            ASSERT_GT(g.normalized().dot(p.normal), 0.0) << file << ": the gradient turns against a normal";
            turned += g.normalized().dot(p.normal) < 0.9;
        }
        EXPECT_LE(double(turned), (sparse ? 0.03 : 0.0) * double(points.size())) << file;
    }
}

// The issue's figure, every input point within 1e-3 of the diagonal, on
// the sparse kitten scan (5,210 points, thin ears): balls that must grow to
// 15 points there span more bend than a quadric follows, and at the default
// min_points the worst point stays near 3e-3 whatever the accuracy asked
// for. Balls of 6 points and an accuracy of 7e-4 bring every point within
// 9.4e-4. The report's worst and mean are the fit's own.
TEST(MpuField, SparseScanFitsEveryPointWithinAThousandthOfItsSize) {
    const std::vector<MpuPoint> points = loadPath(std::string(ISOTRACE_SOURCE_DIR) + "/scenes/scans/kitten.xyz");
    MpuOptions options;
    options.accuracy = 7e-4;
    options.minPoints = 6;
    MpuReport report;
    const MpuField f = MpuField::fit(points, options, &report);
    const double diagonal = diagonalOf(points);
    double sum = 0;
    for (const MpuPoint& p : points) {
        Vec3 g;
        sum += std::abs(f.valueAndGradient(p.position, g)) / g.norm() / diagonal;
    }
    std::printf("kitten.xyz: worst point %.3g, mean %.2g of the diagonal\n", report.maxError, report.meanError);
    EXPECT_LT(worstDistance(f, points), 1e-3 * diagonal);
    EXPECT_NEAR(report.maxError, worstDistance(f, points) / diagonal, 1e-12);
    EXPECT_NEAR(report.meanError, sum / double(points.size()), 1e-12);
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

// Sphere tracing steps by the safe distance: no point within it may have
// the other sign. Points near the surface (where steps are short and the
// bound matters most) and anywhere in the domain, on a scan whose fit has
// sharp (max and min) pieces and balls grown over sparse data.
TEST(MpuField, SafeDistanceHoldsNoZero) {
    const std::vector<MpuPoint> points = load("oni.pwn");
    MpuReport report;
    const MpuField f = MpuField::fit(points, {}, &report);
    ASSERT_GT(report.edges + report.corners, 0u);
    const Box3 domain = f.bounds();
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> g;
    const double diagonal = domain.extent().norm();
    int useful = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        Vec3 x;
        if (trial % 2) {
            const MpuPoint& p = points[size_t(u(rng) * double(points.size()))];
            x = p.position + 0.02 * diagonal * g(rng) * p.normal;
        } else {
            x = domain.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(domain.extent() * 1.2) - 0.1 * domain.extent();
        }
        double safe = 0;
        const double fx = f.valueAndSafeDistance(x, safe);
        ASSERT_NEAR(fx, f.value(x), 1e-9 * (1 + std::abs(fx)));  // sums in another order
        ASSERT_GE(safe, 0.0);
        // Within about a hundredth of the diagonal, f is close to a distance.
        useful += safe > 0.1 * std::min(std::abs(fx), 0.01 * diagonal);
        for (int i = 0; i < 40; ++i) {
            const double reach = i < 10 ? safe : safe * std::cbrt(u(rng));  // the sphere itself, then inside
            const Vec3 y = x + reach * Vec3(g(rng), g(rng), g(rng)).normalized();
            ASSERT_EQ(f.value(y) > 0, fx > 0) << "trial " << trial << ": f " << fx << ", safe " << safe;
        }
    }
    std::printf("safe distances above a tenth of min(|f|, 0.01 diagonal): %d of 2000\n", useful);
    EXPECT_GT(useful, 1500) << "the radius is not uselessly small";
}

// Ranges over boxes hold every value inside (they decide which cells can
// hold surface).
TEST(MpuField, RangesHoldTheValuesInTheirBoxes) {
    const std::vector<MpuPoint> points = load("oni.pwn");
    const MpuField f = MpuField::fit(points);
    const Box3 domain = f.bounds();
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    int excluding = 0;
    for (int trial = 0; trial < 600; ++trial) {
        const Vec3 corner = domain.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(domain.extent());
        const Box3 box(corner, corner + domain.extent() * (0.005 + 0.1 * u(rng)));
        const Interval range = f.range(box);
        excluding += !range.containsZero();
        for (int i = 0; i < 30; ++i) {
            const double v = f.value(box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent()));
            ASSERT_GE(v, range.lo) << "trial " << trial;
            ASSERT_LE(v, range.hi) << "trial " << trial;
        }
    }
    EXPECT_GT(excluding, 300) << "ranges prove most boxes away from the surface empty";
}

// A tracer's list with its single-piece locals first sums those in vector
// lanes: N, W and their gradients must be the plain sums', for lists of
// every length modulo the lane count (partial runs of lanes), on a fit with
// sharp locals among the single ones.
TEST(MpuField, SumsInVectorLanesAreThePlainSums) {
    const MpuField f = MpuField::fit(isotrace::testing::sampleDrilledCube(20000, 5));
    const Box3 domain = f.bounds();
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<uint32_t> list;
    int mixed = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const Vec3 p = domain.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(domain.extent());
        f.localsTouching(Box3(p, p), list);
        // Not every local of the list: every length, both kinds.
        list.resize(list.size() - rng() % (list.size() / 2 + 1));
        const size_t singles = f.singlesFirst(list).singles;
        mixed += singles > 0 && singles < list.size();
        const MpuBlendSums plain = f.blendSums(p, {list}), lanes = f.blendSums(p, {list, singles});
        const double scale =
            MpuField::kSumRelativeError * (1.0 + std::abs(plain.N) + plain.gradientN.norm() + plain.W);
        ASSERT_NEAR(lanes.N, plain.N, scale) << "trial " << trial << ", " << singles << " of " << list.size();
        ASSERT_NEAR(lanes.W, plain.W, scale) << "trial " << trial;
        ASSERT_LE((lanes.gradientN - plain.gradientN).norm(), scale) << "trial " << trial;
        ASSERT_LE((lanes.gradientW - plain.gradientW).norm(), scale) << "trial " << trial;
        ASSERT_NEAR(f.numerator(p, {list, singles}), plain.N, scale) << "trial " << trial;
    }
    EXPECT_GT(mixed, 50) << "lists holding both kinds of local were tested";
}
