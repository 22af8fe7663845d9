// Pearson's chi-square goodness-of-fit test, as Mitsuba 3 and pbrt-v4 test
// their sampling routines: histogram the samples over cells, compare with
// the counts the density predicts, pool cells expecting fewer than 5.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace isotrace::testing {

/// The regularized upper incomplete gamma function Q(a, x) (Numerical
/// Recipes' series and continued fraction).
inline double incompleteGammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    const double logPrefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 100000 && std::abs(term) > 1e-16 * std::abs(sum); ++n) sum += term *= x / (a + n);
        return 1.0 - sum * std::exp(logPrefix);
    }
    const double tiny = 1e-300;
    double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1) < 1e-16) break;
    }
    return std::exp(logPrefix) * h;
}

struct ChiSquareResult {
    double statistic = 0.0;
    int degreesOfFreedom = 0;
    double pValue = 1.0;
    /// Samples in cells the density calls impossible (always a failure).
    double impossible = 0.0;
};

/// `observed` and `expected` counts per cell (same length, same total).
inline ChiSquareResult chiSquareTest(const std::vector<double>& observed, const std::vector<double>& expected) {
    ChiSquareResult r;
    double pooledObserved = 0, pooledExpected = 0;
    std::vector<size_t> regular;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] <= 0) {
            r.impossible += observed[i];
        } else if (expected[i] < 5) {
            pooledObserved += observed[i];
            pooledExpected += expected[i];
        } else {
            regular.push_back(i);
        }
    }
    // A pool still expecting fewer than 5 (a sliver of the density's
    // support that a cell's midpoints missed) joins the smallest regular
    // cell, as the test's approximation needs.
    if (pooledExpected > 0 && pooledExpected < 5 && !regular.empty()) {
        const auto smallest = std::min_element(regular.begin(), regular.end(),
                                               [&](size_t a, size_t b) { return expected[a] < expected[b]; });
        pooledObserved += observed[*smallest];
        pooledExpected += expected[*smallest];
        regular.erase(smallest);
    }
    int cells = 0;
    for (size_t i : regular) {
        const double d = observed[i] - expected[i];
        r.statistic += d * d / expected[i];
        ++cells;
    }
    if (pooledExpected > 0) {
        const double d = pooledObserved - pooledExpected;
        r.statistic += d * d / pooledExpected;
        ++cells;
    }
    r.degreesOfFreedom = cells - 1;
    r.pValue = r.degreesOfFreedom > 0 ? incompleteGammaQ(0.5 * r.degreesOfFreedom, 0.5 * r.statistic) : 1.0;
    return r;
}

/// Chi-square test of a routine sampling unit directions against its
/// solid-angle density: cells of equal solid angle in (cos theta about +y,
/// phi), expected counts from the density integrated over each cell by a
/// `refine` x `refine` midpoint rule. `sample(i)` returns direction i (a
/// zero vector for a sample that failed) and `pdf(w)` its density.
template <class Vec, class Sample, class Pdf>
ChiSquareResult directionChiSquare(int samples, Sample&& sample, Pdf&& pdf, int zBins = 20, int phiBins = 40,
                                   int refine = 6) {
    const double pi = 3.14159265358979323846;
    std::vector<double> observed(size_t(zBins) * phiBins, 0.0), expected(observed.size(), 0.0);
    auto cellOf = [&](const Vec& w) {
        const int zi = std::min(zBins - 1, int((w.y() + 1) * 0.5 * zBins));
        double phi = std::atan2(w.z(), w.x());
        if (phi < 0) phi += 2 * pi;
        const int pi_ = std::min(phiBins - 1, int(phi / (2 * pi) * phiBins));
        return size_t(std::max(0, zi)) * phiBins + size_t(std::max(0, pi_));
    };
    // A sample where the density is zero is a bug whatever the cells say;
    // cells whose midpoints all miss a thin lobe are not.
    double impossible = 0.0;
    for (int i = 0; i < samples; ++i) {
        const Vec w = sample(i);
        if (!(w.squaredNorm() > 0)) continue;
        observed[cellOf(w)] += 1;
        if (!(pdf(w) > 0)) impossible += 1;
    }
    const double cellArea = 4 * pi / (double(zBins) * phiBins), subArea = cellArea / (refine * refine);
    for (int zi = 0; zi < zBins; ++zi)
        for (int p = 0; p < phiBins; ++p)
            for (int a = 0; a < refine; ++a)
                for (int b = 0; b < refine; ++b) {
                    const double z = -1 + 2 * (zi + (a + 0.5) / refine) / zBins;
                    const double phi = 2 * pi * (p + (b + 0.5) / refine) / phiBins;
                    const double r = std::sqrt(std::max(0.0, 1 - z * z));
                    expected[size_t(zi) * phiBins + p] += pdf(Vec(r * std::cos(phi), z, r * std::sin(phi))) * subArea * samples;
                }
    // Cells the rule found empty join the pooled cell instead of failing.
    for (size_t i = 0; i < expected.size(); ++i)
        if (expected[i] <= 0 && observed[i] > 0) expected[i] = 1e-300;
    ChiSquareResult result = chiSquareTest(observed, expected);
    result.impossible = impossible;
    return result;
}

}  // namespace isotrace::testing
