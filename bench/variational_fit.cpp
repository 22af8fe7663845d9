// Solve time of variational implicit surfaces against the number of
// constraints (Turk and O'Brien 2002 needed 1 min 43 s for 1,600 on a
// 195 MHz workstation). Constraints come in boundary/normal pairs on a
// torus, a surface with curvature of both signs.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "bench_support.h"
#include "geometry/variational/rbf_solver.h"

using namespace isotrace;
using namespace isotrace::geometry;

int main() {
    std::printf("constraints  unknowns  median solve (s)  max residual  reciprocal condition\n");
    for (int constraints : {1000, 1600, 2000, 5000, 10000}) {
        // Points on a torus (major 1, minor 0.4), spread by a golden-ratio lattice.
        std::vector<OrientedPoint> points;
        const int count = constraints / 2;
        for (int i = 0; i < count; ++i) {
            const double u = 2 * std::numbers::pi * (i + 0.5) / count;
            const double v = 2 * std::numbers::pi * std::fmod(i * 0.6180339887498949, 1.0);
            const Vec3 ring(std::cos(u), 0, std::sin(u));
            const Vec3 n = std::cos(v) * ring + Vec3(0, std::sin(v), 0);
            points.push_back({ring + 0.4 * n, n});
        }
        const ConstraintSet set = constraintsFromOrientedPoints(points, defaultNormalOffset(points), false);
        FitReport report;
        const int runs = constraints >= 10000 ? 1 : 3;
        const double seconds = bench::medianSeconds(runs, [&] { fitVariationalField(set, &report); });
        std::printf("%11d  %8zu  %16.3f  %12.2e  %20.2e\n", constraints, report.unknowns, seconds, report.maxResidual,
                    report.reciprocalCondition);
    }
    return 0;
}
