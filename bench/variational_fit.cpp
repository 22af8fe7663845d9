// Solve time of variational implicit surfaces against the number of
// constraints (Turk and O'Brien 2002 needed 1 min 43 s for 1,600 on a
// 195 MHz workstation). Constraints come in boundary/normal pairs on a
// torus, a surface with curvature of both signs. The dense solver runs up
// to 10,000 constraints; the partitioned one (local interpolants blended)
// from 2,000 to 1,000,000, with the largest residual and the fitted
// surface's distance to the true torus (first order, at 20,000 points of
// it, over the diagonal), and both fits compared where both run.
//
//   variational_fit [largest partitioned count]     (default 1000000)
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "bench_support.h"
#include "geometry/pointsets/variational_partition.h"
#include "geometry/variational/rbf_solver.h"

using namespace isotrace;
using namespace isotrace::geometry;

namespace {

constexpr double kMajor = 1.0, kMinor = 0.4;

// Points on the torus spread by a golden-ratio lattice, outward normals.
std::vector<OrientedPoint> torusPoints(int count, double phase = 0.0) {
    std::vector<OrientedPoint> points;
    for (int i = 0; i < count; ++i) {
        const double u = 2 * std::numbers::pi * (i + 0.5 + phase) / count;
        const double v = 2 * std::numbers::pi * std::fmod(i * 0.6180339887498949 + phase, 1.0);
        const Vec3 ring(std::cos(u), 0, std::sin(u));
        const Vec3 n = std::cos(v) * ring + Vec3(0, std::sin(v), 0);
        points.push_back({ring + kMinor * n, n});
    }
    return points;
}

double peakMegabytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;
}

// Largest first-order distance |f| / |grad f| at points of the true torus
// between the samples, over the torus' diagonal.
template <class Field>
double truthDistance(const Field& f) {
    const double diagonal = Vec3(2 * (kMajor + kMinor), 2 * kMinor, 2 * (kMajor + kMinor)).norm();
    double worst = 0.0;
    for (const OrientedPoint& p : torusPoints(20000, 0.37)) {
        Vec3 g;
        const double v = f.valueAndGradient(p.position, g);
        worst = std::max(worst, std::abs(v) / g.norm());
    }
    return worst / diagonal;
}

}  // namespace

int main(int argc, char** argv) {
    const int largest = argc > 1 ? std::atoi(argv[1]) : 1000000;
    std::printf("dense solver\nconstraints  unknowns  median solve (s)  max residual  reciprocal condition  truth distance\n");
    for (int constraints : {1000, 1600, 2000, 5000, 10000}) {
        const std::vector<OrientedPoint> points = torusPoints(constraints / 2);
        const ConstraintSet set = constraintsFromOrientedPoints(points, defaultNormalOffset(points), false);
        FitReport report;
        VariationalField field;
        const int runs = constraints >= 10000 ? 1 : 3;
        const double seconds = bench::medianSeconds(runs, [&] { field = fitVariationalField(set, &report); });
        std::printf("%11d  %8zu  %16.3f  %12.2e  %20.2e  %14.2e\n", constraints, report.unknowns, seconds,
                    report.maxResidual, report.reciprocalCondition, truthDistance(field));
    }
    std::printf("\npartitioned solver (2 threads)\nconstraints  interpolants  mean/largest  solve (s)  peak (MB)  max residual  "
                "truth distance\n");
    for (int constraints : {2000, 10000, 100000, 1000000}) {
        if (constraints > largest) break;
        const std::vector<OrientedPoint> points = torusPoints(constraints / 2);
        const ConstraintSet set = constraintsFromOrientedPoints(points, defaultNormalOffset(points), false);
        PartitionReport report;
        MpuField field;
        const double seconds =
            bench::medianSeconds(constraints >= 100000 ? 1 : 3, [&] { field = fitPartitionedVariationalField(set, &report); });
        std::printf("%11d  %12zu  %6.0f/%-5zu  %9.3f  %9.0f  %12.2e  %14.2e\n", constraints, report.locals,
                    report.meanLocal, report.largestLocal, seconds, peakMegabytes(), report.maxResidual,
                    truthDistance(field));
    }
    return 0;
}
