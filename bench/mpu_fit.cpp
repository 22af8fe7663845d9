// MPU fits of large oriented point sets with a known truth: the drilled cube
// of tests/support/drilled_cube.h (sharp edges) sampled at 100,000 and
// 1,000,000 points, exact and with noise along the normals. For each: fit
// time, peak memory of the process so far, local functions, the input
// points' distance to the fit (max and mean, over the diagonal) and the
// truth's distance to the fit (20,000 points of the true surface, the fit's
// root along the true normal; max and mean over the diagonal).
//
//   mpu_fit [largest count]        (default 1000000)
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>

#include "geometry/pointsets/mpu_field.h"
#include "support/drilled_cube.h"

using namespace isotrace::geometry;
using isotrace::testing::sampleDrilledCube;

namespace {

double peakMegabytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux reports kilobytes
}

// The root of f along p + t n nearest t = 0 within |t| <= reach (scan and
// bisection), or reach when there is none.
double distanceAlong(const MpuField& f, const Vec3& p, const Vec3& n, double reach) {
    const double f0 = f.value(p), step = reach / 400;
    for (double t = step; t <= reach; t += step)
        for (double s : {t, -t})
            if ((f.value(p + s * n) > 0) != (f0 > 0)) {
                double lo = s - (s > 0 ? step : -step), hi = s;
                for (int k = 0; k < 40; ++k) {
                    const double mid = 0.5 * (lo + hi);
                    ((f.value(p + mid * n) > 0) == (f0 > 0) ? lo : hi) = mid;
                }
                return std::abs(0.5 * (lo + hi));
            }
    return f0 == 0 ? 0.0 : reach;
}

}  // namespace

int main(int argc, char** argv) {
    const size_t largest = argc > 1 ? size_t(std::atoll(argv[1])) : 1000000;
    const double diagonal = 2.0 * std::sqrt(3.0);
    const std::vector<MpuPoint> truth = sampleDrilledCube(20000, 99);
    std::printf("drilled cube ([-1, 1]^3 minus a cylinder of radius 0.5), default options (accuracy 0.002)\n");
    std::printf("%9s %7s %8s %9s %8s %14s %14s %14s\n", "points", "noise", "fit (s)", "peak (MB)", "locals",
                "points max", "points mean", "truth max/mean");
    for (size_t count : {size_t(100000), size_t(1000000)}) {
        if (count > largest) break;
        for (double noise : {0.0, 5e-4 * diagonal}) {
            const std::vector<MpuPoint> points = sampleDrilledCube(count, 7, noise);
            MpuReport report;
            const MpuField f = MpuField::fit(points, {}, &report);
            double mean = 0;
            for (const MpuPoint& p : points) {
                Vec3 g;
                mean += std::abs(f.valueAndGradient(p.position, g)) / g.norm();
            }
            mean /= double(points.size()) * diagonal;
            double worstTruth = 0, meanTruth = 0;
            for (const MpuPoint& p : truth) {
                const double d = distanceAlong(f, p.position, p.normal, 0.02 * diagonal) / diagonal;
                worstTruth = std::max(worstTruth, d);
                meanTruth += d / double(truth.size());
            }
            std::printf("%9zu %7.0e %8.2f %9.0f %8zu %14.2e %14.2e %7.1e/%.1e\n", count, noise / diagonal, report.seconds,
                        peakMegabytes(), report.localFunctions, report.maxError, mean, worstTruth, meanTruth);
            std::fflush(stdout);
        }
    }
    return 0;
}
