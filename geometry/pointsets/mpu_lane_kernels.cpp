// The MPU lane sums (mpu_lane_kernels.h) for one instruction set: compiled
// once per set by geometry/CMakeLists.txt (isotrace_isa_kernels), with
// ISOTRACE_ISA naming the set and its namespace. Everything here has
// internal linkage or lives in that namespace, and it includes no header
// whose inline functions other files compile too (no Eigen, no library
// types): wider code must not stand in for a narrower one's definitions
// (the test IsaKernels.ExportOnlyTheirOwnSymbols checks the objects).
#include <experimental/simd>

#include "geometry/lanes.h"
#include "geometry/pointsets/mpu_lane_kernels.h"

#ifndef ISOTRACE_ISA
#error "compiled through isotrace_isa_kernels, which names the instruction set"
#endif

namespace isotrace::geometry::ISOTRACE_ISA {

namespace {

using L = std::experimental::native_simd<double>;
using std::experimental::reduce;

// Calls visit(load, valid) for each run of L::size() of the rows `listed`
// names: load(column) gathers that column of the run's rows; lanes past the
// list's end repeat its first row and are not valid.
template <class Visit>
[[gnu::always_inline]] inline void forLaneRuns(const double* rows, const uint32_t* listed, size_t count,
                                               Visit&& visit) {
    constexpr size_t kWidth = L::size();
    for (size_t first = 0; first < count; first += kWidth) {
        const size_t run = count - first < kWidth ? count - first : kWidth;
        const double* row[kWidth];
        for (size_t j = 0; j < kWidth; ++j) row[j] = rows + kMpuLaneColumns * listed[first + (j < run ? j : 0)];
        auto load = [&](int column) { return L([&](auto j) { return row[j][column]; }); };
        visit(load, firstLanes<L>(run));
    }
}

void addSums(const double* rows, const uint32_t* listed, size_t count, const double* p, MpuLaneSums& s) {
    L W = 0, N = 0, wx = 0, wy = 0, wz = 0, nx = 0, ny = 0, nz = 0;
    forLaneRuns(rows, listed, count, [&](auto&& column, const L::mask_type& valid) {
        const L rx = p[0] - column(CenterX), ry = p[1] - column(CenterY), rz = p[2] - column(CenterZ);
        const L inverseR2 = column(InverseRadius2);
        const L s1 = L(1) - (rx * rx + ry * ry + rz * rz) * inverseR2;
        const L::mask_type inside = valid && s1 > L(0);
        if (none_of(inside)) return;  // no ball holds p: the quadrics are not needed
        const L sigma = select(inside, s1, L(0)), w = sigma * sigma * sigma;
        const L axx = column(Axx), axy = column(Axy), axz = column(Axz), ayy = column(Ayy), ayz = column(Ayz),
                azz = column(Azz);
        const L arx = axx * rx + axy * ry + axz * rz, ary = axy * rx + ayy * ry + ayz * rz,
                arz = axz * rx + ayz * ry + azz * rz;
        const L gx = column(Gx), gy = column(Gy), gz = column(Gz);
        const L q = column(C0) + (gx * rx + gy * ry + gz * rz) + (rx * arx + ry * ary + rz * arz);
        const L dw = L(-6) * sigma * sigma * inverseR2;  // grad w = dw r
        W += w;
        N += w * q;
        wx += dw * rx;
        wy += dw * ry;
        wz += dw * rz;
        nx += dw * rx * q + w * (gx + L(2) * arx);
        ny += dw * ry * q + w * (gy + L(2) * ary);
        nz += dw * rz * q + w * (gz + L(2) * arz);
    });
    s.W += reduce(W);
    s.N += reduce(N);
    s.gradientW[0] += reduce(wx);
    s.gradientW[1] += reduce(wy);
    s.gradientW[2] += reduce(wz);
    s.gradientN[0] += reduce(nx);
    s.gradientN[1] += reduce(ny);
    s.gradientN[2] += reduce(nz);
}

double numerator(const double* rows, const uint32_t* listed, size_t count, const double* p) {
    L N = 0;
    forLaneRuns(rows, listed, count, [&](auto&& column, const L::mask_type& valid) {
        const L rx = p[0] - column(CenterX), ry = p[1] - column(CenterY), rz = p[2] - column(CenterZ);
        const L s1 = L(1) - (rx * rx + ry * ry + rz * rz) * column(InverseRadius2);
        const L::mask_type inside = valid && s1 > L(0);
        if (none_of(inside)) return;
        const L sigma = select(inside, s1, L(0));
        const L axx = column(Axx), axy = column(Axy), axz = column(Axz), ayy = column(Ayy), ayz = column(Ayz),
                azz = column(Azz);
        const L q = column(C0) + (column(Gx) * rx + column(Gy) * ry + column(Gz) * rz) +
                    (rx * (axx * rx + axy * ry + axz * rz) + ry * (axy * rx + ayy * ry + ayz * rz) +
                     rz * (axz * rx + ayz * ry + azz * rz));
        N += sigma * sigma * sigma * q;
    });
    return reduce(N);
}

int alongSegment(const double* rows, const uint32_t* listed, size_t count, const double* p0, const double* D,
                 double* wholeOut, MpuPartialTerm partial, void* context) {
    const double DD = D[0] * D[0] + D[1] * D[1] + D[2] * D[2];
    L whole[9] = {};  // the sum of the terms whose ball holds the whole segment
    int met = 0;
    forLaneRuns(rows, listed, count, [&](auto&& load, const L::mask_type& valid) {
        using std::experimental::sqrt, std::experimental::popcount;
        // s(u) = 1 - |r0 + u D|^2 / R^2 = s0 + s1 u + s2 u^2; the ball is s > 0,
        // between u = (-r0D -+ sqrt(disc)) / DD.
        const L rx = p0[0] - load(CenterX), ry = p0[1] - load(CenterY), rz = p0[2] - load(CenterZ);
        const L inverseR2 = load(InverseRadius2);
        const L r0D = rx * D[0] + ry * D[1] + rz * D[2], r0r0 = rx * rx + ry * ry + rz * rz;
        const L disc = r0D * r0D + DD * (1.0 / inverseR2 - r0r0);
        const L root = sqrt(select(disc > 0.0, disc, L(0.0)));
        const L enter = greater(L((-r0D - root) / DD), L(0.0)), leave = lesser(L((-r0D + root) / DD), L(1.0));
        const L::mask_type meets = valid && disc > 0.0 && enter < leave;
        if (none_of(meets)) return;
        met += popcount(meets);
        const L s0 = 1.0 - r0r0 * inverseR2, s1 = -2.0 * r0D * inverseR2, s2 = L(-DD) * inverseR2;
        // s^2 and s^3.
        const L a0 = s0 * s0, a1 = 2.0 * s0 * s1, a2 = s1 * s1 + 2.0 * s0 * s2, a3 = 2.0 * s1 * s2, a4 = s2 * s2;
        const L w[7] = {a0 * s0, a0 * s1 + a1 * s0, a0 * s2 + a1 * s1 + a2 * s0, a1 * s2 + a2 * s1 + a3 * s0,
                        a2 * s2 + a3 * s1 + a4 * s0, a3 * s2 + a4 * s1, a4 * s2};
        // Q along the segment, about the ball's centre: q0 + q1 u + q2 u^2.
        const L axx = load(Axx), axy = load(Axy), axz = load(Axz), ayy = load(Ayy), ayz = load(Ayz), azz = load(Azz);
        const L arx = axx * rx + axy * ry + axz * rz, ary = axy * rx + ayy * ry + ayz * rz,
                arz = axz * rx + ayz * ry + azz * rz;
        const L adx = axx * D[0] + axy * D[1] + axz * D[2], ady = axy * D[0] + ayy * D[1] + ayz * D[2],
                adz = axz * D[0] + ayz * D[1] + azz * D[2];
        const L gx = load(Gx), gy = load(Gy), gz = load(Gz);
        const L q0 = load(C0) + (gx * rx + gy * ry + gz * rz) + (rx * arx + ry * ary + rz * arz);
        const L q1 = (gx * D[0] + gy * D[1] + gz * D[2]) + 2.0 * (rx * adx + ry * ady + rz * adz);
        const L q2 = D[0] * adx + D[1] * ady + D[2] * adz;
        L term[9];
        for (int k = 0; k <= 8; ++k) term[k] = 0.0;
        for (int i = 0; i <= 6; ++i) {
            term[i] += w[i] * q0;
            term[i + 1] += w[i] * q1;
            term[i + 2] += w[i] * q2;
        }
        const L::mask_type throughout = meets && enter <= 0.0 && leave >= 1.0;
        for (int k = 0; k <= 8; ++k) whole[k] += select(throughout, term[k], L(0.0));
        const L::mask_type partly = meets && !throughout;
        if (none_of(partly)) return;
        for (size_t j = 0; j < L::size(); ++j) {
            if (!partly[j]) continue;
            double poly[9];
            for (int k = 0; k <= 8; ++k) poly[k] = term[k][j];
            partial(context, poly, enter[j], leave[j]);
        }
    });
    for (int k = 0; k <= 8; ++k) wholeOut[k] += reduce(whole[k]);
    return met;
}

}  // namespace

extern const MpuLaneKernels kMpuLaneKernels = {addSums, numerator, alongSegment};

}  // namespace isotrace::geometry::ISOTRACE_ISA
