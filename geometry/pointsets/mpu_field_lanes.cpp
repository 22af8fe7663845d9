// The single-piece locals' share of an MPU field's sums over a tracer's
// list, Lanes::size() locals at a time: gathered from the field's lane rows
// (each quadric taken about its ball's centre, so one offset r serves the
// weight and the quadric). Built for the machine's widest vectors.
#include <algorithm>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "geometry/lanes.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/segment_polynomial.h"

namespace isotrace::geometry {

namespace {

using std::experimental::reduce;

// Calls visit(load, valid) for each run of Lanes::size() of the rows
// `listed` names: load(column) gathers that column of the run's rows; lanes
// past the list's end repeat its first row and are not valid.
template <class Row, class Visit>
void forLaneRuns(const std::vector<Row>& rows, std::span<const uint32_t> listed, Visit&& visit) {
    constexpr size_t kWidth = Lanes::size();
    for (size_t first = 0; first < listed.size(); first += kWidth) {
        const size_t count = std::min(kWidth, listed.size() - first);
        uint32_t index[kWidth];
        for (size_t j = 0; j < kWidth; ++j) index[j] = listed[first + (j < count ? j : 0)];
        auto load = [&](int column) { return Lanes([&](auto j) { return rows[index[j]].values[column]; }); };
        visit(load, firstLanes(count));
    }
}

#if defined(__AVX512F__)
using FloatLanes = std::experimental::native_simd<float>;
static_assert(FloatLanes::size() == 16);

// GCC 12 warns falsely of the undefined pass-through operand inside its
// AVX-512 shuffle intrinsics.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
// Sixteen rows of sixteen floats, one register each, turned into sixteen
// columns: pairs, then quads interleaved within 128-bit blocks, then the
// blocks themselves, 64 shuffles for what lane-by-lane inserts took 224.
[[gnu::always_inline]] inline void transposeRows(__m512 r[16]) {
    __m512 t[16];
    for (int k = 0; k < 8; ++k) {
        t[2 * k] = _mm512_unpacklo_ps(r[2 * k], r[2 * k + 1]);
        t[2 * k + 1] = _mm512_unpackhi_ps(r[2 * k], r[2 * k + 1]);
    }
    auto pd = [](__m512 v) { return _mm512_castps_pd(v); };
    for (int k = 0; k < 4; ++k) {
        r[4 * k + 0] = _mm512_castpd_ps(_mm512_unpacklo_pd(pd(t[4 * k + 0]), pd(t[4 * k + 2])));
        r[4 * k + 1] = _mm512_castpd_ps(_mm512_unpackhi_pd(pd(t[4 * k + 0]), pd(t[4 * k + 2])));
        r[4 * k + 2] = _mm512_castpd_ps(_mm512_unpacklo_pd(pd(t[4 * k + 1]), pd(t[4 * k + 3])));
        r[4 * k + 3] = _mm512_castpd_ps(_mm512_unpackhi_pd(pd(t[4 * k + 1]), pd(t[4 * k + 3])));
    }
    // r[4k + m] now holds rows 4k..4k+3 of columns m, m + 4, m + 8, m + 12,
    // one per 128-bit block.
    for (int k = 0; k < 2; ++k)
        for (int m = 0; m < 4; ++m) {
            t[8 * k + m] = _mm512_shuffle_f32x4(r[8 * k + m], r[8 * k + 4 + m], 0x88);
            t[8 * k + 4 + m] = _mm512_shuffle_f32x4(r[8 * k + m], r[8 * k + 4 + m], 0xdd);
        }
    for (int m = 0; m < 4; ++m) {
        r[m] = _mm512_shuffle_f32x4(t[m], t[8 + m], 0x88);
        r[8 + m] = _mm512_shuffle_f32x4(t[m], t[8 + m], 0xdd);
        r[4 + m] = _mm512_shuffle_f32x4(t[4 + m], t[12 + m], 0x88);
        r[12 + m] = _mm512_shuffle_f32x4(t[4 + m], t[12 + m], 0xdd);
    }
}
#pragma GCC diagnostic pop

// Calls visit(column, valid) for each run of sixteen of the rows `listed`
// names: column[c] holds column c of the run's rows; lanes past the list's
// end repeat its first row and are not valid.
template <class Row, class Visit>
[[gnu::always_inline]] inline void forFloatLaneRuns(const std::vector<Row>& rows, std::span<const uint32_t> listed,
                                                 Visit&& visit) {
    constexpr size_t kWidth = FloatLanes::size();
    const FloatLanes lane([](auto j) { return float(j); });
    for (size_t first = 0; first < listed.size(); first += kWidth) {
        const size_t count = std::min(kWidth, listed.size() - first);
        __m512 r[kWidth];
        for (size_t j = 0; j < kWidth; ++j) r[j] = _mm512_load_ps(rows[listed[first + (j < count ? j : 0)]].values);
        transposeRows(r);
        const FloatLanes column[16] = {FloatLanes(r[0]),  FloatLanes(r[1]),  FloatLanes(r[2]),  FloatLanes(r[3]),
                                       FloatLanes(r[4]),  FloatLanes(r[5]),  FloatLanes(r[6]),  FloatLanes(r[7]),
                                       FloatLanes(r[8]),  FloatLanes(r[9]),  FloatLanes(r[10]), FloatLanes(r[11]),
                                       FloatLanes(r[12]), FloatLanes(r[13]), FloatLanes(r[14]), FloatLanes(r[15])};
        visit(column, lane < float(count));
    }
}

// p as two floats, hi + lo: (hi - c) + lo keeps r = p - c to a float's
// precision of r itself, not of p.
struct SplitPoint {
    float hi[3], lo[3];
    explicit SplitPoint(const Vec3& p) {
        for (int k = 0; k < 3; ++k) {
            hi[k] = float(p[k]);
            lo[k] = float(p[k] - double(hi[k]));
        }
    }
};

constexpr bool kFloatLanes = true;
using PointLanes = FloatLanes;

// Calls visit(rx, ry, rz, column, valid) for each run of lanes of the
// rows `listed` names: r = p - the balls' centres (columns 0 to 2), and
// column(c) the run's column c. Single-precision rows here.
template <class DoubleRow, class FloatRow, class Visit>
[[gnu::always_inline]] inline void forPointLaneRuns(const std::vector<DoubleRow>&, const std::vector<FloatRow>& rows,
                                                    const Vec3& p, std::span<const uint32_t> listed, Visit&& visit) {
    const SplitPoint at(p);
    forFloatLaneRuns(rows, listed, [&](const FloatLanes* column, const FloatLanes::mask_type& valid) {
        visit((at.hi[0] - column[0]) + at.lo[0], (at.hi[1] - column[1]) + at.lo[1], (at.hi[2] - column[2]) + at.lo[2],
              [column](int c) -> const FloatLanes& { return column[c]; }, valid);
    });
}
#else
constexpr bool kFloatLanes = false;
using PointLanes = Lanes;

// The same from the double rows, gathered lane by lane.
template <class DoubleRow, class FloatRow, class Visit>
[[gnu::always_inline]] inline void forPointLaneRuns(const std::vector<DoubleRow>& rows, const std::vector<FloatRow>&,
                                                    const Vec3& p, std::span<const uint32_t> listed, Visit&& visit) {
    forLaneRuns(rows, listed, [&](auto&& load, const Lanes::mask_type& valid) {
        visit(p.x() - load(0), p.y() - load(1), p.z() - load(2), load, valid);
    });
}
#endif

}  // namespace

double MpuField::laneRelativeError() { return kFloatLanes ? 2e-5 : 1e-12; }

void MpuField::addSingleLanes(const Vec3& p, std::span<const uint32_t> rows, MpuBlendSums& s) const {
    static_assert(CenterX == 0 && CenterY == 1 && CenterZ == 2, "forPointLaneRuns reads the centres there");
    using L = PointLanes;
    L W = 0, N = 0, wx = 0, wy = 0, wz = 0, nx = 0, ny = 0, nz = 0;
    forPointLaneRuns(laneRows_, floatLaneRows_, p, rows,
                     [&](const L& rx, const L& ry, const L& rz, auto&& column, const L::mask_type& valid) {
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
    s.gradientW += Vec3(reduce(wx), reduce(wy), reduce(wz));
    s.gradientN += Vec3(reduce(nx), reduce(ny), reduce(nz));
}

double MpuField::singleLanesNumerator(const Vec3& p, std::span<const uint32_t> rows) const {
    using L = PointLanes;
    L N = 0;
    forPointLaneRuns(laneRows_, floatLaneRows_, p, rows,
                     [&](const L& rx, const L& ry, const L& rz, auto&& column, const L::mask_type& valid) {
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

int MpuField::addSinglesAlongSegment(const Vec3& p0, const Vec3& D, std::span<const uint32_t> singles,
                                     SegmentPolynomialSum<8>& sum) const {
    const double DD = D.squaredNorm();
    Lanes whole[9] = {};  // the sum of the terms whose ball holds the whole segment
    int met = 0;
    forLaneRuns(laneRows_, singles, [&](auto&& load, const Lanes::mask_type& valid) {
        using std::experimental::sqrt, std::experimental::popcount;
        // s(u) = 1 - |r0 + u D|^2 / R^2 = s0 + s1 u + s2 u^2; the ball is s > 0,
        // between u = (-r0D -+ sqrt(disc)) / DD.
        const Lanes rx = p0.x() - load(CenterX), ry = p0.y() - load(CenterY), rz = p0.z() - load(CenterZ);
        const Lanes inverseR2 = load(InverseRadius2);
        const Lanes r0D = rx * D.x() + ry * D.y() + rz * D.z(), r0r0 = rx * rx + ry * ry + rz * rz;
        const Lanes disc = r0D * r0D + DD * (1.0 / inverseR2 - r0r0);
        const Lanes root = sqrt(select(disc > 0.0, disc, Lanes(0.0)));
        const Lanes enter = greater(Lanes((-r0D - root) / DD), Lanes(0.0)),
                    leave = lesser(Lanes((-r0D + root) / DD), Lanes(1.0));
        const Lanes::mask_type meets = valid && disc > 0.0 && enter < leave;
        if (none_of(meets)) return;
        met += popcount(meets);
        const Lanes s0 = 1.0 - r0r0 * inverseR2, s1 = -2.0 * r0D * inverseR2, s2 = Lanes(-DD) * inverseR2;
        // s^2 and s^3.
        const Lanes a0 = s0 * s0, a1 = 2.0 * s0 * s1, a2 = s1 * s1 + 2.0 * s0 * s2, a3 = 2.0 * s1 * s2, a4 = s2 * s2;
        const Lanes w[7] = {a0 * s0, a0 * s1 + a1 * s0, a0 * s2 + a1 * s1 + a2 * s0, a1 * s2 + a2 * s1 + a3 * s0,
                            a2 * s2 + a3 * s1 + a4 * s0, a3 * s2 + a4 * s1, a4 * s2};
        // Q along the segment, about the ball's centre: q0 + q1 u + q2 u^2.
        const Lanes axx = load(Axx), axy = load(Axy), axz = load(Axz), ayy = load(Ayy), ayz = load(Ayz),
                    azz = load(Azz);
        const Lanes arx = axx * rx + axy * ry + axz * rz, ary = axy * rx + ayy * ry + ayz * rz,
                    arz = axz * rx + ayz * ry + azz * rz;
        const Lanes adx = axx * D.x() + axy * D.y() + axz * D.z(), ady = axy * D.x() + ayy * D.y() + ayz * D.z(),
                    adz = axz * D.x() + ayz * D.y() + azz * D.z();
        const Lanes gx = load(Gx), gy = load(Gy), gz = load(Gz);
        const Lanes q0 = load(C0) + (gx * rx + gy * ry + gz * rz) + (rx * arx + ry * ary + rz * arz);
        const Lanes q1 = (gx * D.x() + gy * D.y() + gz * D.z()) + 2.0 * (rx * adx + ry * ady + rz * adz);
        const Lanes q2 = D.x() * adx + D.y() * ady + D.z() * adz;
        Lanes term[9];
        for (int k = 0; k <= 8; ++k) term[k] = 0.0;
        for (int i = 0; i <= 6; ++i) {
            term[i] += w[i] * q0;
            term[i + 1] += w[i] * q1;
            term[i + 2] += w[i] * q2;
        }
        const Lanes::mask_type throughout = meets && enter <= 0.0 && leave >= 1.0;
        for (int k = 0; k <= 8; ++k) whole[k] += select(throughout, term[k], Lanes(0.0));
        const Lanes::mask_type partly = meets && !throughout;
        if (none_of(partly)) return;
        for (size_t j = 0; j < Lanes::size(); ++j) {
            if (!partly[j]) continue;
            Monomials<8> poly;
            for (int k = 0; k <= 8; ++k) poly[k] = term[k][j];
            sum.add(poly, enter[j], leave[j]);
        }
    });
    Monomials<8> poly;
    for (int k = 0; k <= 8; ++k) poly[k] = reduce(whole[k]);
    sum.add(poly, 0.0, 1.0);
    return met;
}

}  // namespace isotrace::geometry
