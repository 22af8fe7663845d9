#include "geometry/variational/variational_field.h"

#include "geometry/instruction_set.h"
#include "geometry/variational/rbf_kernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {

RbfTerms termsOf(const VariationalField& f) {
    return {f.centers.x(), f.centers.y(), f.centers.z(), f.weights.data(), f.centers.size()};
}

}  // namespace

const RbfKernels& rbfKernels() {
    static const RbfKernels& chosen =
        tableForActiveSet(sse2::kRbfKernels, avx2::kRbfKernels, avx512::kRbfKernels);
    return chosen;
}

double VariationalField::value(const Vec3& x) const {
    double sum = rbfKernels().value(termsOf(*this), x.data());
    sum += constant + linear.dot(x);
    // grad |d|^3 = 3 |d| d.
    for (size_t k = 0; k < gradientCenters.size(); ++k) {
        const Vec3 d = x - gradientCenters[k];
        sum -= 3.0 * d.norm() * gradientWeights[k].dot(d);
    }
    return sum;
}

double VariationalField::valueAndGradient(const Vec3& x, Vec3& gradient) const {
    Vec3 sums;
    double sum = rbfKernels().valueAndGradient(termsOf(*this), x.data(), sums.data());
    sum += constant + linear.dot(x);
    Vec3 g = linear + sums;
    // Hessian of |d|^3: 3 (|d| I + d d^T / |d|), zero at d = 0.
    for (size_t k = 0; k < gradientCenters.size(); ++k) {
        const Vec3 d = x - gradientCenters[k];
        const Vec3& b = gradientWeights[k];
        const double r = d.norm();
        sum -= 3.0 * r * b.dot(d);
        if (r > 0) g -= 3.0 * (r * b + (d.dot(b) / r) * d);
    }
    gradient = g;
    return sum;
}

namespace {

// Bounds of f over a box of half-diagonal h around its centre x0, from the
// exact value, gradient and Hessian at x0 (sums with all their
// cancellation) and two bounds on how fast things change in the box:
//   ||D^2 f(x)|| <= sum_i 6 |w_i| r_i,max          (|D^2 r^3| = 6 r)
//   ||D^3 f(x)|| <= sum_i 12 |w_i|                 (|D^3 r^3| <= 12)
// Gradient terms b_k have a fourth derivative singular at their centres, so
// they enter through their Hessian bound 12 |b_k| only.
struct BoxBounds {
    double value, gradientNorm;
    double hessianAnywhere;  ///< bound on ||D^2 f|| over the box
    double hessianAtCenter;  ///< ||D^2 f_values(x0)|| (Frobenius, an upper bound of the 2-norm)
    double thirdDerivative;  ///< bound on ||D^3 f_values|| anywhere
    double hermiteHessian;   ///< bound on the gradient terms' ||D^2|| anywhere
};

// Value, gradient and the value terms' Hessian at x, with the bounds that
// do not depend on a box: it runs at every sphere-tracing step.
BoxBounds taylorAt(const VariationalField& f, const Vec3& x) {
    BoxBounds b{0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    RbfTaylorSums t;
    rbfKernels().taylor(termsOf(f), x.data(), t);
    double gx = t.gradient[0], gy = t.gradient[1], gz = t.gradient[2];
    const double hxx = t.hxx, hyy = t.hyy, hzz = t.hzz, hxy = t.hxy, hxz = t.hxz, hyz = t.hyz;
    b.value = t.value + f.constant + f.linear.dot(x);
    gx += f.linear.x();
    gy += f.linear.y();
    gz += f.linear.z();
    for (size_t k = 0; k < f.gradientCenters.size(); ++k) {
        const Vec3 d = x - f.gradientCenters[k];
        const Vec3& w = f.gradientWeights[k];
        const double r = d.norm();
        b.value -= 3.0 * r * w.dot(d);
        if (r > 0) {
            const Vec3 g = 3.0 * (r * w + (d.dot(w) / r) * d);
            gx -= g.x();
            gy -= g.y();
            gz -= g.z();
        }
        b.hermiteHessian += 12.0 * w.norm();
    }
    b.gradientNorm = std::sqrt(gx * gx + gy * gy + gz * gz);
    // Frobenius norm: an upper bound of the spectral norm.
    b.hessianAtCenter = std::sqrt(hxx * hxx + hyy * hyy + hzz * hzz + 2 * (hxy * hxy + hxz * hxz + hyz * hyz));
    b.thirdDerivative = 12.0 * t.absoluteWeights;
    return b;
}

BoxBounds boxBounds(const VariationalField& f, const Box3& box) {
    BoxBounds b = taylorAt(f, box.center());
    // Farthest distance from each centre to the box.
    const double hessianAnywhere = rbfKernels().hessianBound(termsOf(f), box.lower.data(), box.upper.data());
    b.hessianAnywhere = hessianAnywhere + b.hermiteHessian;
    return b;
}

}  // namespace

VariationalField::PointBounds VariationalField::boundsAt(const Vec3& x) const {
    const BoxBounds b = taylorAt(*this, x);
    return {b.value, b.gradientNorm, b.hessianAtCenter + b.hermiteHessian, b.thirdDerivative};
}

double VariationalField::valueAndSafeDistance(const Vec3& x, double& safeDistance) const {
    const BoxBounds b = taylorAt(*this, x);
    const double v = std::abs(b.value), g = b.gradientNorm, h = b.hessianAtCenter + b.hermiteHessian,
                 t = b.thirdDerivative;
    // |f(y)| >= |f(x)| - g s - h s^2 / 2 - t s^3 / 6 for |y - x| <= s: the
    // root of the right side is a safe radius. Each term alone reaching |f|
    // bounds the root from above; bisect below the smallest.
    auto margin = [&](double s) { return v - g * s - 0.5 * h * s * s - t * s * s * s / 6.0; };
    double hi = std::numeric_limits<double>::infinity();
    if (g > 0) hi = std::min(hi, v / g);
    if (h > 0) hi = std::min(hi, std::sqrt(2 * v / h));
    if (t > 0) hi = std::min(hi, std::cbrt(6 * v / t));
    double lo = 0.0;
    if (std::isfinite(hi))
        for (int i = 0; i < 40; ++i) {
            const double mid = 0.5 * (lo + hi);
            (margin(mid) > 0 ? lo : hi) = mid;
        }
    safeDistance = lo;
    return b.value;
}

Interval VariationalField::range(const Box3& box) const {
    const BoxBounds b = boxBounds(*this, box);
    const double h = box.halfDiagonal();
    // Taylor with the remainder bounded by the Hessian anywhere, or with the
    // Hessian at the centre and the third derivative; the smaller is sound.
    const double second = 0.5 * b.hessianAnywhere * h * h;
    const double third = 0.5 * (b.hessianAtCenter + b.hermiteHessian) * h * h + b.thirdDerivative * h * h * h / 6.0;
    const double spread = b.gradientNorm * h + std::min(second, third);
    return {b.value - spread, b.value + spread};
}

double VariationalField::lipschitz(const Box3& box) const {
    const BoxBounds b = boxBounds(*this, box);
    const double h = box.halfDiagonal();
    return b.gradientNorm + std::min(b.hessianAnywhere * h,
                                     (b.hessianAtCenter + b.hermiteHessian) * h + 0.5 * b.thirdDerivative * h * h);
}

}  // namespace isotrace::geometry
