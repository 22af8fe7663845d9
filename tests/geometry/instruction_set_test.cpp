// The vector kernels of every instruction set this CPU runs (and that the
// process's cap allows) against plain sums: each must give the same sums up
// to the order of summation, so that an AVX2 node and an AVX-512 node of a
// farm render the same image within rounding.
#include "geometry/instruction_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/pointsets/mpu_lane_kernels.h"
#include "geometry/pointsets/mpu_model_kernels.h"
#include "geometry/variational/rbf_kernels.h"

using namespace isotrace::geometry;

namespace {

struct KernelSet {
    InstructionSet set;
    const MpuLaneKernels* mpu;
    const RbfKernels* rbf;
    const MpuModelKernels* model;
};

// The sets this CPU can run, baseline first.
std::vector<KernelSet> runnableSets() {
    std::vector<KernelSet> sets = {
        {InstructionSet::SSE2, &sse2::kMpuLaneKernels, &sse2::kRbfKernels, &sse2::kMpuModelKernels}};
    const InstructionSet cpu = cpuInstructionSet();
    if (cpu >= InstructionSet::AVX2)
        sets.push_back({InstructionSet::AVX2, &avx2::kMpuLaneKernels, &avx2::kRbfKernels, &avx2::kMpuModelKernels});
    if (cpu >= InstructionSet::AVX512)
        sets.push_back(
            {InstructionSet::AVX512, &avx512::kMpuLaneKernels, &avx512::kRbfKernels, &avx512::kMpuModelKernels});
    return sets;
}

struct alignas(64) Row {
    double values[kMpuLaneColumns] = {};
};

// Random balls around the origin with random quadrics.
std::vector<Row> randomRows(size_t count, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Row> rows(count);
    for (Row& r : rows) {
        for (int k = 0; k < 3; ++k) r.values[k] = 0.5 * u(rng);
        const double radius = 0.3 + 0.5 * std::abs(u(rng));
        r.values[InverseRadius2] = 1 / (radius * radius);
        for (int k = C0; k <= Azz; ++k) r.values[k] = u(rng);
    }
    return rows;
}

// The MPU sums one term at a time, in the plainest form.
MpuLaneSums plainSums(const std::vector<Row>& rows, const std::vector<uint32_t>& listed, const double* p) {
    MpuLaneSums s;
    for (uint32_t i : listed) {
        const double* v = rows[i].values;
        const double r[3] = {p[0] - v[CenterX], p[1] - v[CenterY], p[2] - v[CenterZ]};
        const double t = 1 - (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) * v[InverseRadius2];
        if (t <= 0) continue;
        const double A[3][3] = {{v[Axx], v[Axy], v[Axz]}, {v[Axy], v[Ayy], v[Ayz]}, {v[Axz], v[Ayz], v[Azz]}};
        double Ar[3], q = v[C0];
        for (int a = 0; a < 3; ++a) {
            Ar[a] = A[a][0] * r[0] + A[a][1] * r[1] + A[a][2] * r[2];
            q += v[Gx + a] * r[a] + r[a] * Ar[a];
        }
        const double w = t * t * t, dw = -6 * t * t * v[InverseRadius2];
        s.W += w;
        s.N += w * q;
        for (int a = 0; a < 3; ++a) {
            s.gradientW[a] += dw * r[a];
            s.gradientN[a] += dw * r[a] * q + w * (v[Gx + a] + 2 * Ar[a]);
        }
    }
    return s;
}

}  // namespace

TEST(InstructionSet, NamesRoundTripAndUnknownNamesAreRefused) {
    for (InstructionSet set : {InstructionSet::SSE2, InstructionSet::AVX2, InstructionSet::AVX512})
        EXPECT_EQ(instructionSetNamed(instructionSetName(set)), set);
    EXPECT_THROW(instructionSetNamed("avx"), std::invalid_argument);
    EXPECT_LE(activeInstructionSet(), cpuInstructionSet());
}

// Every list length modulo the widest lane count (8), so partial runs of
// lanes are covered; relative to the magnitudes summed, the sets agree with
// the plain sums to 1e-12 (they differ only in the order of the sums).
TEST(InstructionSet, MpuLaneKernelsOfEverySetAreThePlainSums) {
    std::mt19937_64 rng(5);
    const std::vector<Row> rows = randomRows(64, rng);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    const std::vector<KernelSet> sets = runnableSets();
    int inside = 0;
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<uint32_t> listed;
        const size_t count = size_t(trial % 37);
        for (size_t k = 0; k < count; ++k) listed.push_back(uint32_t(rng() % rows.size()));
        const double p[3] = {u(rng), u(rng), u(rng)};
        const MpuLaneSums plain = plainSums(rows, listed, p);
        inside += plain.W > 0;
        const double scale = 1e-12 * (1 + std::abs(plain.N) + plain.W + std::abs(plain.gradientN[0]) +
                                      std::abs(plain.gradientN[1]) + std::abs(plain.gradientN[2]));
        for (const KernelSet& k : sets) {
            MpuLaneSums s;
            k.mpu->addSums(rows.front().values, listed.data(), listed.size(), p, s);
            const auto name = instructionSetName(k.set);
            ASSERT_NEAR(s.N, plain.N, scale) << name << ", trial " << trial;
            ASSERT_NEAR(s.W, plain.W, scale) << name;
            for (int a = 0; a < 3; ++a) {
                ASSERT_NEAR(s.gradientN[a], plain.gradientN[a], scale) << name;
                ASSERT_NEAR(s.gradientW[a], plain.gradientW[a], scale) << name;
            }
            ASSERT_NEAR(k.mpu->numerator(rows.front().values, listed.data(), listed.size(), p), plain.N, scale)
                << name;
        }
    }
    EXPECT_GT(inside, 100) << "points inside some ball were tested";
}

// Along a segment, every set hands over the same terms: the whole segment's
// sum and the partial terms, each checked at points of the segment against
// the plain sum there.
TEST(InstructionSet, MpuSegmentTermsOfEverySetSumToThePlainValues) {
    std::mt19937_64 rng(9);
    const std::vector<Row> rows = randomRows(40, rng);
    std::uniform_real_distribution<double> u(-0.8, 0.8);
    struct Partial {
        double monomials[9], enter, leave;
    };
    for (const KernelSet& k : runnableSets()) {
        for (int trial = 0; trial < 50; ++trial) {
            std::vector<uint32_t> listed;
            for (size_t i = 0; i < size_t(1 + trial % 23); ++i) listed.push_back(uint32_t(rng() % rows.size()));
            const double p0[3] = {u(rng), u(rng), u(rng)}, D[3] = {u(rng), u(rng), u(rng)};
            double whole[9] = {};
            std::vector<Partial> partials;
            auto keep = [](void* context, const double* m, double enter, double leave) {
                Partial part;
                std::copy(m, m + 9, part.monomials);
                part.enter = enter;
                part.leave = leave;
                static_cast<std::vector<Partial>*>(context)->push_back(part);
            };
            k.mpu->alongSegment(rows.front().values, listed.data(), listed.size(), p0, D, whole, keep, &partials);
            for (double t : {0.1, 0.37, 0.5, 0.81}) {
                auto poly = [t](const double* m) {
                    double v = 0;
                    for (int d = 8; d >= 0; --d) v = v * t + m[d];
                    return v;
                };
                double along = poly(whole);
                for (const Partial& part : partials)
                    if (t >= part.enter && t <= part.leave) along += poly(part.monomials);
                const double p[3] = {p0[0] + t * D[0], p0[1] + t * D[1], p0[2] + t * D[2]};
                const MpuLaneSums plain = plainSums(rows, listed, p);
                ASSERT_NEAR(along, plain.N, 1e-9 * (1 + std::abs(plain.N))) << instructionSetName(k.set);
            }
        }
    }
}

TEST(InstructionSet, RbfKernelsOfEverySetAreThePlainSums) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (size_t n : {size_t(1), size_t(7), size_t(33), size_t(1001)}) {
        std::vector<double> x(n), y(n), z(n), w(n);
        for (size_t i = 0; i < n; ++i) x[i] = u(rng), y[i] = u(rng), z[i] = u(rng), w[i] = u(rng);
        const RbfTerms terms{x.data(), y.data(), z.data(), w.data(), n};
        const double p[3] = {0.3, -0.2, 0.7}, lo[3] = {-0.1, -0.2, -0.3}, hi[3] = {0.4, 0.1, 0.2};
        double value = 0, gradient[3] = {}, magnitude = 0, hessianBound = 0, absolute = 0;
        for (size_t i = 0; i < n; ++i) {
            const double d[3] = {p[0] - x[i], p[1] - y[i], p[2] - z[i]};
            const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            value += w[i] * r * r * r;
            for (int a = 0; a < 3; ++a) gradient[a] += 3 * w[i] * r * d[a];
            magnitude += std::abs(w[i]) * (r * r * r + 3 * r * r);
            double far2 = 0;
            const double c[3] = {x[i], y[i], z[i]};
            for (int a = 0; a < 3; ++a) {
                const double f = std::max(std::abs(c[a] - lo[a]), std::abs(c[a] - hi[a]));
                far2 += f * f;
            }
            hessianBound += 6 * std::abs(w[i]) * std::sqrt(far2);
            absolute += std::abs(w[i]);
        }
        const double tolerance = 1e-13 * (1 + magnitude);
        for (const KernelSet& k : runnableSets()) {
            const auto name = instructionSetName(k.set);
            EXPECT_NEAR(k.rbf->value(terms, p), value, tolerance) << name << ", " << n << " terms";
            double g[3];
            EXPECT_NEAR(k.rbf->valueAndGradient(terms, p, g), value, tolerance) << name;
            RbfTaylorSums t;
            k.rbf->taylor(terms, p, t);
            EXPECT_NEAR(t.value, value, tolerance) << name;
            EXPECT_NEAR(t.absoluteWeights, absolute, 1e-13 * absolute) << name;
            for (int a = 0; a < 3; ++a) {
                EXPECT_NEAR(g[a], gradient[a], tolerance) << name;
                EXPECT_NEAR(t.gradient[a], gradient[a], tolerance) << name;
            }
            EXPECT_NEAR(k.rbf->hessianBound(terms, lo, hi), hessianBound, 1e-13 * hessianBound) << name;
        }
    }
}

// The numerator models' sums over a box: every set gives the baseline's
// sums, the bounds' shares too (each lane takes the same branches; only the
// order of the sums changes), for counts that leave partial runs of lanes.
TEST(InstructionSet, MpuModelKernelsOfEverySetAgree) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-1, 1);
    using C = MpuModelColumn;
    for (size_t count : {size_t(1), size_t(5), size_t(8), size_t(13), size_t(40)}) {
        const size_t stride = (count + kMpuModelColumnPadding - 1) / kMpuModelColumnPadding * kMpuModelColumnPadding;
        std::vector<double> columns(stride * C::kColumns, 0.0);
        auto at = [&](C::Column c, size_t k) -> double& { return columns[size_t(c) * stride + k]; };
        for (size_t k = 0; k < count; ++k) {
            const double radius = 0.4 + 0.6 * std::abs(u(rng));
            for (C::Column c : {C::CenterX, C::CenterY, C::CenterZ}) at(c, k) = 0.4 * u(rng);
            at(C::Radius, k) = radius;
            at(C::InverseRadius2, k) = 1 / (radius * radius);
            for (int c = C::OriginX; c <= C::C0; ++c) at(C::Column(c), k) = u(rng);
            at(C::Curvature, k) = 2.0;
        }
        const double c[3] = {0.05, -0.02, 0.03};
        for (double h : {0.02, 0.3}) {
            const double lower[3] = {c[0] - h, c[1] - h, c[2] - h}, upper[3] = {c[0] + h, c[1] + h, c[2] + h};
            const double rho = h * std::sqrt(3.0);
            std::vector<MpuColumnSums> results;
            for (const KernelSet& k : runnableSets()) {
                results.emplace_back();
                k.model->sumColumns(columns.data(), stride, count, c, lower, upper, rho, results.back());
            }
            const MpuColumnSums& base = results.front();
            EXPECT_GT(base.ownThird, 0.0) << "the balls reach the box";
            for (size_t s = 1; s < results.size(); ++s) {
                const MpuColumnSums& r = results[s];
                auto close = [](double a, double b) { return std::abs(a - b) <= 1e-12 * (1 + std::abs(b)); };
                EXPECT_TRUE(close(r.value, base.value)) << count << " locals, set " << s;
                for (int j = 0; j < 3; ++j) EXPECT_TRUE(close(r.gradient[j], base.gradient[j]));
                for (int j = 0; j < 6; ++j) EXPECT_TRUE(close(r.hessian[j], base.hessian[j]));
                for (int j = 0; j < 10; ++j) EXPECT_TRUE(close(r.tensor[j], base.tensor[j]));
                EXPECT_TRUE(close(r.ownThird, base.ownThird) && close(r.fourth, base.fourth) &&
                            close(r.apart, base.apart) && close(r.scale, base.scale) &&
                            close(r.directValue, base.directValue) && close(r.directSlope, base.directSlope))
                    << count << " locals, set " << s;
            }
        }
    }
}
