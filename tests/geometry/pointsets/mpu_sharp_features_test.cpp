// Sharp features of MPU fits against the part they were sampled from: a
// cube [-1, 1]^3 with a cylindrical hole of radius 0.5 along z, 50,000
// oriented points. Its edges (the cube's twelve and the hole's two rims)
// must come back within 2e-3 of the diagonal, with the normals on either
// side within 5 degrees of the faces' at that distance from the edge; a fit
// of smooth functions only rounds them and fails the same test.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/pointsets/mpu_field.h"
#include "support/drilled_cube.h"

using namespace isotrace::geometry;

using isotrace::testing::kHoleRadius;
using isotrace::testing::sampleDrilledCube;

namespace {

const double kDiagonal = 2.0 * std::sqrt(3.0);

// A point of a true edge with the unit normals of its two faces.
struct EdgePoint {
    Vec3 position, normal1, normal2;
};

std::vector<EdgePoint> edgePoints() {
    std::vector<EdgePoint> out;
    // The cube's edges, away from its corners: every pair of adjacent faces.
    for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b) {
            const int c = 3 - a - b;
            for (double sa : {-1.0, 1.0})
                for (double sb : {-1.0, 1.0})
                    for (int k = 0; k < 9; ++k) {
                        Vec3 p = Vec3::Zero(), n1 = Vec3::Zero(), n2 = Vec3::Zero();
                        p[a] = sa, p[b] = sb, p[c] = -0.8 + 0.2 * k;
                        n1[a] = sa, n2[b] = sb;
                        out.push_back({p, n1, n2});
                    }
        }
    // The hole's rims: the cap (z = +-1) meets the wall.
    for (double sz : {-1.0, 1.0})
        for (int k = 0; k < 24; ++k) {
            const double phi = 2.0 * std::numbers::pi * (k + 0.5) / 24;
            const Vec3 radial(std::cos(phi), std::sin(phi), 0);
            out.push_back({kHoleRadius * radial + Vec3(0, 0, sz), Vec3(0, 0, sz), -radial});
        }
    return out;
}

// The root of f on the segment p + t d, |t| <= reach, nearest t = 0, by a
// scan and bisection; NaN when f keeps its sign.
double rootNear(const MpuField& f, const Vec3& p, const Vec3& d, double reach) {
    const double f0 = f.value(p);
    if (f0 == 0) return 0;
    const double step = 1e-4;
    for (double t = step; t <= reach; t += step)
        for (double s : {t, -t}) {
            if ((f.value(p + s * d) > 0) == (f0 > 0)) continue;
            double lo = s - (s > 0 ? step : -step), hi = s;
            for (int k = 0; k < 40; ++k) {
                const double mid = 0.5 * (lo + hi);
                ((f.value(p + mid * d) > 0) == (f0 > 0) ? lo : hi) = mid;
            }
            return 0.5 * (lo + hi);
        }
    return NAN;
}

struct EdgeReport {
    double worstEdgeDistance = 0;  ///< along the bisector, over the diagonal
    double worstNormalDegrees = 0;
};

// How far the fitted surface lies from each true edge (measured along the
// bisector of its faces' normals, at least the distance to the surface),
// and how far its normals turn from the faces' at `away` from the edge.
EdgeReport measureEdges(const MpuField& f, double away) {
    EdgeReport report;
    for (const EdgePoint& e : edgePoints()) {
        const Vec3 bisector = (e.normal1 + e.normal2).normalized();
        const double t = rootNear(f, e.position, bisector, 0.1);
        report.worstEdgeDistance = std::max(report.worstEdgeDistance, std::isnan(t) ? 1.0 : std::abs(t) / kDiagonal);
        for (const auto& [n, other] : {std::pair{e.normal1, e.normal2}, std::pair{e.normal2, e.normal1}}) {
            const Vec3 inFace = -(other - other.dot(n) * n).normalized();
            const Vec3 onFace = e.position + away * inFace;
            const double s = rootNear(f, onFace, n, 0.1);
            Vec3 g;
            f.valueAndGradient(onFace + (std::isnan(s) ? 0.0 : s) * n, g);
            const double degrees = std::acos(std::clamp(g.normalized().dot(n), -1.0, 1.0)) * 180 / std::numbers::pi;
            report.worstNormalDegrees = std::max(report.worstNormalDegrees, std::isnan(s) ? 180.0 : degrees);
        }
    }
    return report;
}

}  // namespace

TEST(MpuSharpFeatures, EdgesOfADrilledCubeStaySharp) {
    const std::vector<MpuPoint> points = sampleDrilledCube(50000, 7);
    const double tolerance = 2e-3;
    MpuOptions options;
    MpuReport report;
    const MpuField sharp = MpuField::fit(points, options, &report);
    const EdgeReport edges = measureEdges(sharp, tolerance * kDiagonal);
    std::printf("sharp: %zu local functions (%zu edges, %zu corners), %.2f s; edges within %.2g of the diagonal, "
                "normals beside them within %.2f degrees; worst point %.2g\n",
                report.localFunctions, report.edges, report.corners, report.seconds, edges.worstEdgeDistance,
                edges.worstNormalDegrees, report.maxError);
    EXPECT_GT(report.edges, 0u);
    EXPECT_GT(report.corners, 0u);
    EXPECT_LT(edges.worstEdgeDistance, tolerance);
    EXPECT_LT(edges.worstNormalDegrees, 5.0);
    EXPECT_LT(report.maxError, 2 * options.accuracy);

    // Smooth functions alone must round the same edges: the test can tell.
    options.sharpFeatures = false;
    const MpuField smooth = MpuField::fit(points, options, &report);
    const EdgeReport rounded = measureEdges(smooth, tolerance * kDiagonal);
    std::printf("smooth only: %zu local functions, %.2f s; edges within %.2g, normals within %.2f degrees\n",
                report.localFunctions, report.seconds, rounded.worstEdgeDistance, rounded.worstNormalDegrees);
    EXPECT_EQ(report.edges + report.corners, 0u);
    EXPECT_GT(rounded.worstNormalDegrees, 5.0);
}
