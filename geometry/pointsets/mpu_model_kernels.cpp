// The numerator models' sums over single-piece locals (mpu_model_kernels.h)
// for one instruction set: compiled once per set by geometry/CMakeLists.txt
// (isotrace_isa_kernels), with ISOTRACE_ISA naming the set and its
// namespace. Everything here is always inlined, has internal linkage or lives
// in that namespace, and no Eigen or library type is included: wider code
// must not stand in for a narrower one's definitions (the test
// IsaKernelSymbols checks the objects).
#include <experimental/simd>

#include "geometry/lanes.h"
#include "geometry/pointsets/mpu_model_kernels.h"
#include "geometry/pointsets/mpu_weight_bounds.h"

#ifndef ISOTRACE_ISA
#error "compiled through isotrace_isa_kernels, which names the instruction set"
#endif

namespace isotrace::geometry::ISOTRACE_ISA {

namespace {

static_assert(Lanes::size() <= kMpuModelColumnPadding, "columns are padded for the widest lanes");

// Single-piece locals from the columns, Lanes::size() at a time; the
// columns are padded to whole vectors, and the padding's lanes are masked.
struct LaneLoader {
    const double* columns;
    size_t stride;
    size_t first;  ///< the first local of the lanes
    [[gnu::always_inline]] Lanes operator()(MpuModelColumn::Column c) const {
        return Lanes(columns + size_t(c) * stride + first, std::experimental::element_aligned);
    }
};

// The lanes' quadrics at p (value and gradient), and what each adds to N's
// Taylor terms there: TaylorSums::add, lane by lane. Every term carries
// sigma, so a lane whose ball misses p (or a padding lane) adds nothing.
struct LaneTerms {
    Lanes q, gqx, gqy, gqz;
    Lanes value, gx, gy, gz, hxx, hxy, hxz, hyy, hyz, hzz;
};

[[gnu::always_inline]] inline LaneTerms laneTerms(const LaneLoader& load, const double* p, const Lanes::mask_type& valid) {
    using C = MpuModelColumn;
    LaneTerms t;
    const Lanes yx = p[0] - load(C::OriginX), yy = p[1] - load(C::OriginY), yz = p[2] - load(C::OriginZ);
    const Lanes axx = load(C::Axx), axy = load(C::Axy), axz = load(C::Axz), ayy = load(C::Ayy), ayz = load(C::Ayz),
                azz = load(C::Azz);
    const Lanes ayX = axx * yx + axy * yy + axz * yz, ayY = axy * yx + ayy * yy + ayz * yz,
                ayZ = axz * yx + ayz * yy + azz * yz;
    const Lanes gx = load(C::Gx), gy = load(C::Gy), gz = load(C::Gz);
    t.q = load(C::C0) + (gx * yx + gy * yy + gz * yz) + (yx * ayX + yy * ayY + yz * ayZ);
    t.gqx = gx + 2.0 * ayX;
    t.gqy = gy + 2.0 * ayY;
    t.gqz = gz + 2.0 * ayZ;
    const Lanes rx = p[0] - load(C::CenterX), ry = p[1] - load(C::CenterY), rz = p[2] - load(C::CenterZ);
    const Lanes inverseR2 = load(C::InverseRadius2);
    const Lanes s = 1.0 - (rx * rx + ry * ry + rz * rz) * inverseR2;
    const Lanes sigma = select(valid && s > 0.0, s, Lanes(0.0)), w = sigma * sigma * sigma;
    const Lanes dsx = 2.0 * inverseR2 * rx, dsy = 2.0 * inverseR2 * ry, dsz = 2.0 * inverseR2 * rz;
    const Lanes dwScale = -3.0 * sigma * sigma;
    const Lanes dwx = dwScale * dsx, dwy = dwScale * dsy, dwz = dwScale * dsz;
    const Lanes outer = 6.0 * sigma * t.q, diagonal = 6.0 * sigma * sigma * t.q * inverseR2;
    t.value = w * t.q;
    t.gx = t.q * dwx + w * t.gqx;
    t.gy = t.q * dwy + w * t.gqy;
    t.gz = t.q * dwz + w * t.gqz;
    t.hxx = outer * dsx * dsx + dwx * t.gqx + t.gqx * dwx + 2.0 * w * axx - diagonal;
    t.hxy = outer * dsx * dsy + dwx * t.gqy + t.gqx * dwy + 2.0 * w * axy;
    t.hxz = outer * dsx * dsz + dwx * t.gqz + t.gqx * dwz + 2.0 * w * axz;
    t.hyy = outer * dsy * dsy + dwy * t.gqy + t.gqy * dwy + 2.0 * w * ayy - diagonal;
    t.hyz = outer * dsy * dsz + dwy * t.gqz + t.gqy * dwz + 2.0 * w * ayz;
    t.hzz = outer * dsz * dsz + dwz * t.gqz + t.gqz * dwz + 2.0 * w * azz - diagonal;
    return t;
}

// Adds each `holds` lane's third derivatives of w Q at p to tensor
// (xxx xxy xxz xyy xyz xzz yyy yyz yzz zzz): with a = grad sigma =
// -2 r / R^2, grad w = 3 sigma^2 a, Hw = 6 sigma a a^T - 6 sigma^2 / R^2 I and
//   D3w_ijk = 6 a_i a_j a_k - 12 sigma / R^2 (d_ik a_j + d_jk a_i + d_ij a_k),
//   D3(w Q)_ijk = D3w_ijk Q + Hw_ij gQ_k + Hw_ik gQ_j + Hw_jk gQ_i
//                 + dw_i HQ_jk + dw_j HQ_ik + dw_k HQ_ij,  HQ = 2 A.
[[gnu::always_inline]] inline void addThirdDerivatives(const LaneLoader& load, const double* p, const LaneTerms& t,
                                                       const Lanes::mask_type& holds, Lanes* tensor) {
    using C = MpuModelColumn;
    const Lanes inverseR2 = load(C::InverseRadius2);
    const Lanes r[3] = {p[0] - load(C::CenterX), p[1] - load(C::CenterY), p[2] - load(C::CenterZ)};
    const Lanes sigma = select(holds, Lanes(1.0 - (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) * inverseR2), Lanes(0.0));
    const Lanes a[3] = {-2.0 * inverseR2 * r[0], -2.0 * inverseR2 * r[1], -2.0 * inverseR2 * r[2]};
    const Lanes g[3] = {t.gqx, t.gqy, t.gqz};
    const Lanes dw[3] = {3.0 * sigma * sigma * a[0], 3.0 * sigma * sigma * a[1], 3.0 * sigma * sigma * a[2]};
    const Lanes twoA[6] = {2.0 * load(C::Axx), 2.0 * load(C::Axy), 2.0 * load(C::Axz),
                           2.0 * load(C::Ayy), 2.0 * load(C::Ayz), 2.0 * load(C::Azz)};
    auto hq = [&](int i, int j) {
        static constexpr int kIndex[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
        return twoA[kIndex[i][j]];
    };
    const Lanes sixSigma = 6.0 * sigma, diagonal = 6.0 * sigma * sigma * inverseR2, twelve = 12.0 * sigma * inverseR2;
    auto hw = [&](int i, int j) { return Lanes(sixSigma * a[i] * a[j] - (i == j ? diagonal : Lanes(0.0))); };
    int slot = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            for (int k = j; k < 3; ++k, ++slot) {
                Lanes w3 = 6.0 * a[i] * a[j] * a[k];
                if (i == k) w3 -= twelve * a[j];
                if (j == k) w3 -= twelve * a[i];
                if (i == j) w3 -= twelve * a[k];
                const Lanes term = w3 * t.q + hw(i, j) * g[k] + hw(i, k) * g[j] + hw(j, k) * g[i] + dw[i] * hq(j, k) +
                                   dw[j] * hq(i, k) + dw[k] * hq(i, j);
                tensor[slot] += select(holds, term, Lanes(0.0));
            }
}

// The single-piece locals' Taylor terms at c; with a box (centre c, half
// diagonal rho), also their share of M3 and of the sums' size over it.
// Each local's share of M3 is either its own bound (what addLocal gives it)
// or, where its ball holds the whole box (w is smooth over it) and this is
// smaller, its fourth-derivative bound times rho, its third derivatives at
// c going to MpuColumnSums::tensor (see thirdFromCentre in
// mpu_numerator_model.cpp).
void sumColumns(const double* columns, size_t stride, size_t n, const double* c, const double* lower,
                const double* upper, double rho, MpuColumnSums& sums) {
    using C = MpuModelColumn;
    using std::experimental::reduce;
    const bool box = lower != nullptr;
    const double half[3] = {box ? 0.5 * (upper[0] - lower[0]) : 0.0, box ? 0.5 * (upper[1] - lower[1]) : 0.0,
                            box ? 0.5 * (upper[2] - lower[2]) : 0.0};
    Lanes value = 0.0, gx = 0.0, gy = 0.0, gz = 0.0, hxx = 0.0, hxy = 0.0, hxz = 0.0, hyy = 0.0, hyz = 0.0, hzz = 0.0;
    Lanes ownThird = 0.0, scale = 0.0, fourth = 0.0, apart = 0.0;
    Lanes directOwn = 0.0, directValue = 0.0, directSlope = 0.0, directHessian = 0.0;
    Lanes tensor[10];
    for (Lanes& t : tensor) t = 0.0;
    for (size_t first = 0; first < n; first += Lanes::size()) {
        const LaneLoader load{columns, stride, first};
        const Lanes::mask_type valid = firstLanes<Lanes>(n - first);
        const LaneTerms t = laneTerms(load, c, valid);
        value += t.value;
        gx += t.gx;
        gy += t.gy;
        gz += t.gz;
        hxx += t.hxx;
        hxy += t.hxy;
        hxz += t.hxz;
        hyy += t.hyy;
        hyz += t.hyz;
        hzz += t.hzz;
        if (!box) continue;
        // The distances from the ball's centre to the box.
        using std::experimental::abs, std::experimental::sqrt;
        auto gap = [&](C::Column centre, int axis) {
            const Lanes x = load(centre);
            return greater(greater(Lanes(lower[axis] - x), Lanes(0.0)), Lanes(x - upper[axis]));
        };
        auto far = [&](C::Column centre, int axis) {
            const Lanes x = load(centre);
            return greater(Lanes(abs(x - lower[axis])), Lanes(abs(x - upper[axis])));
        };
        const Lanes ex = gap(C::CenterX, 0), ey = gap(C::CenterY, 1), ez = gap(C::CenterZ, 2);
        const Lanes fx = far(C::CenterX, 0), fy = far(C::CenterY, 1), fz = far(C::CenterZ, 2);
        const Lanes gap2 = ex * ex + ey * ey + ez * ez;
        const Lanes nearest = sqrt(gap2), farthest = sqrt(fx * fx + fy * fy + fz * fz);
        const Lanes R = load(C::Radius);
        const Lanes sigmaMax = 1.0 - gap2 * load(C::InverseRadius2);
        const Lanes w1 = mpuWeightSlope(nearest, farthest, R), w2 = weightCurvatureBound(nearest, farthest, R),
                    w3 = weightThirdBound(nearest, farthest, R);
        const Lanes hqNorm = 2.0 * load(C::Curvature);  // at least |u^T Hq u|
        const Symmetric3<Lanes> a{load(C::Axx), load(C::Axy), load(C::Axz), load(C::Ayy), load(C::Ayz), load(C::Azz)};
        const Lanes q0 =
            quadraticRangeOf(t.q, t.gqx, t.gqy, t.gqz, a, Lanes(half[0]), Lanes(half[1]), Lanes(half[2])).magnitude();
        const Lanes q1 = sqrt(t.gqx * t.gqx + t.gqy * t.gqy + t.gqz * t.gqz) + hqNorm * rho;
        // Padding lanes have R = 0: no distance is below it.
        const Lanes::mask_type reaches = valid && nearest < R;
        const Lanes own = w3 * q0 + 3.0 * w2 * q1 + 3.0 * w1 * hqNorm;
        ownThird += select(reaches, own, Lanes(0.0));
        scale += select(reaches, Lanes(sigmaMax * sigmaMax * sigmaMax * q0), Lanes(0.0));
        // (w Q)'''' = w'''' Q + 4 w''' Q' + 6 w'' Q'' (Q''' = 0).
        const Lanes own4 = weightFourthBound(nearest, farthest, R) * q0 + 4.0 * w3 * q1 + 6.0 * w2 * hqNorm;
        const Lanes::mask_type fromCentre = reaches && farthest < R && own4 * rho < own;
        fourth += select(fromCentre, own4, Lanes(0.0));
        const Lanes::mask_type others = reaches && !fromCentre;
        apart += select(others, own, Lanes(0.0));
        if (any_of(fromCentre)) addThirdDerivatives(load, c, t, fromCentre, tensor);
        if (none_of(others)) continue;
        // A ball whose rim crosses the box: w Q - T_i (T_i its Taylor terms
        // at c) is at most max w |Q| + max |T_i| over the box, and likewise
        // for slope and curvature. Near the rim w = sigma^3 is small, and
        // this is well below Taylor's remainder of its own bound, which the
        // jump of w's third derivative at the rim makes large (on the
        // 37,934-vertex model those remainders were most of the value
        // errors).
        const Lanes w0 = sigmaMax * sigmaMax * sigmaMax;
        const Lanes hx = half[0], hy = half[1], hz = half[2];
        const Lanes taylorRange = abs(t.value) + abs(t.gx) * hx + abs(t.gy) * hy + abs(t.gz) * hz +
                                  0.5 * (abs(t.hxx) * hx * hx + abs(t.hyy) * hy * hy + abs(t.hzz) * hz * hz) +
                                  abs(t.hxy) * hx * hy + abs(t.hxz) * hx * hz + abs(t.hyz) * hy * hz;
        const Lanes taylorSlope = sqrt(t.gx * t.gx + t.gy * t.gy + t.gz * t.gz);
        const Lanes taylorHessian = sqrt(t.hxx * t.hxx + t.hyy * t.hyy + t.hzz * t.hzz +
                                         2.0 * (t.hxy * t.hxy + t.hxz * t.hxz + t.hyz * t.hyz));
        const Lanes value = w0 * q0 + taylorRange;
        const Lanes::mask_type direct = others && value < own * (rho * rho * rho / 6.0);
        directOwn += select(direct, own, Lanes(0.0));
        directValue += select(direct, value, Lanes(0.0));
        directSlope += select(direct, Lanes(w1 * q0 + w0 * q1 + taylorSlope + taylorHessian * rho), Lanes(0.0));
        directHessian += select(direct, Lanes(w2 * q0 + 2.0 * w1 * q1 + w0 * hqNorm + taylorHessian), Lanes(0.0));
    }
    sums.value = reduce(value);
    sums.gradient[0] = reduce(gx);
    sums.gradient[1] = reduce(gy);
    sums.gradient[2] = reduce(gz);
    const Lanes* hessian[6] = {&hxx, &hxy, &hxz, &hyy, &hyz, &hzz};
    for (int j = 0; j < 6; ++j) sums.hessian[j] = reduce(*hessian[j]);
    sums.ownThird = reduce(ownThird);
    sums.scale = reduce(scale);
    for (int j = 0; j < 10; ++j) sums.tensor[j] = reduce(tensor[j]);
    sums.fourth = reduce(fourth);
    sums.apart = reduce(apart);
    sums.directOwn = reduce(directOwn);
    sums.directValue = reduce(directValue);
    sums.directSlope = reduce(directSlope);
    sums.directHessian = reduce(directHessian);
}

}  // namespace

extern const MpuModelKernels kMpuModelKernels = {sumColumns};

}  // namespace isotrace::geometry::ISOTRACE_ISA
