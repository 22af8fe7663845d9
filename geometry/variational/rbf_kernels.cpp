// The r^3 sums (rbf_kernels.h) for one instruction set: compiled once per set
// by geometry/CMakeLists.txt (isotrace_isa_kernels). The simd reductions let
// the compiler sum in vector lanes: the order of the sum changes, not its
// accuracy. Like every kernel file it includes no header whose inline
// functions other files compile too (builtins instead of <cmath>).
#include "geometry/variational/rbf_kernels.h"

#ifndef ISOTRACE_ISA
#error "compiled through isotrace_isa_kernels, which names the instruction set"
#endif

namespace isotrace::geometry::ISOTRACE_ISA {

namespace {

double value(const RbfTerms& t, const double* p) {
    const double *cx = t.x, *cy = t.y, *cz = t.z, *w = t.weight;
    const double px = p[0], py = p[1], pz = p[2];
    double sum = 0.0;
#pragma omp simd reduction(+ : sum)
    for (size_t i = 0; i < t.count; ++i) {
        const double dx = px - cx[i], dy = py - cy[i], dz = pz - cz[i];
        const double r2 = dx * dx + dy * dy + dz * dz;
        sum += w[i] * __builtin_sqrt(r2) * r2;
    }
    return sum;
}

double valueAndGradient(const RbfTerms& t, const double* p, double* gradient) {
    const double *cx = t.x, *cy = t.y, *cz = t.z, *w = t.weight;
    const double px = p[0], py = p[1], pz = p[2];
    double sum = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
#pragma omp simd reduction(+ : sum, gx, gy, gz)
    for (size_t i = 0; i < t.count; ++i) {
        const double dx = px - cx[i], dy = py - cy[i], dz = pz - cz[i];
        const double r2 = dx * dx + dy * dy + dz * dz, r = __builtin_sqrt(r2);
        const double wr = w[i] * r;
        sum += wr * r2;
        gx += 3.0 * wr * dx;
        gy += 3.0 * wr * dy;
        gz += 3.0 * wr * dz;
    }
    gradient[0] = gx;
    gradient[1] = gy;
    gradient[2] = gz;
    return sum;
}

void taylor(const RbfTerms& t, const double* p, RbfTaylorSums& s) {
    const double *cx = t.x, *cy = t.y, *cz = t.z, *weights = t.weight;
    const double px = p[0], py = p[1], pz = p[2];
    double value = 0, gx = 0, gy = 0, gz = 0;
    double hxx = 0, hyy = 0, hzz = 0, hxy = 0, hxz = 0, hyz = 0, weightSum = 0;
#pragma omp simd reduction(+ : value, gx, gy, gz, hxx, hyy, hzz, hxy, hxz, hyz, weightSum)
    for (size_t i = 0; i < t.count; ++i) {
        const double dx = px - cx[i], dy = py - cy[i], dz = pz - cz[i];
        const double w = weights[i];
        const double r2 = dx * dx + dy * dy + dz * dz, r = __builtin_sqrt(r2);
        const double wr3 = 3.0 * w * r;
        value += w * r * r2;
        gx += wr3 * dx;
        gy += wr3 * dy;
        gz += wr3 * dz;
        // 3 w (r I + d d^T / r); the second part vanishes with r.
        const double q = r > 0 ? 3.0 * w / r : 0.0;
        hxx += wr3 + q * dx * dx;
        hyy += wr3 + q * dy * dy;
        hzz += wr3 + q * dz * dz;
        hxy += q * dx * dy;
        hxz += q * dx * dz;
        hyz += q * dy * dz;
        weightSum += __builtin_fabs(w);
    }
    s.value = value;
    s.gradient[0] = gx;
    s.gradient[1] = gy;
    s.gradient[2] = gz;
    s.hxx = hxx;
    s.hyy = hyy;
    s.hzz = hzz;
    s.hxy = hxy;
    s.hxz = hxz;
    s.hyz = hyz;
    s.absoluteWeights = weightSum;
}

double hessianBound(const RbfTerms& t, const double* lo, const double* hi) {
    const double *cx = t.x, *cy = t.y, *cz = t.z, *weights = t.weight;
    double sum = 0.0;
#pragma omp simd reduction(+ : sum)
    for (size_t i = 0; i < t.count; ++i) {
        const double ax = __builtin_fabs(cx[i] - lo[0]), bx = __builtin_fabs(cx[i] - hi[0]);
        const double ay = __builtin_fabs(cy[i] - lo[1]), by = __builtin_fabs(cy[i] - hi[1]);
        const double az = __builtin_fabs(cz[i] - lo[2]), bz = __builtin_fabs(cz[i] - hi[2]);
        const double fx = ax > bx ? ax : bx, fy = ay > by ? ay : by, fz = az > bz ? az : bz;
        sum += 6.0 * __builtin_fabs(weights[i]) * __builtin_sqrt(fx * fx + fy * fy + fz * fz);
    }
    return sum;
}

}  // namespace

extern const RbfKernels kRbfKernels = {value, valueAndGradient, taylor, hessianBound};

}  // namespace isotrace::geometry::ISOTRACE_ISA
