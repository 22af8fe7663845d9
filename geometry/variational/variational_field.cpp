#include "variational_field.h"

#include <cmath>

namespace isotrace::geometry {

double VariationalField::value(const Vec3& x) const {
    double sum = constant + linear.dot(x);
    for (size_t i = 0; i < centers.size(); ++i) {
        const double r = (x - centers[i]).norm();
        sum += weights[i] * r * r * r;
    }
    // grad |d|^3 = 3 |d| d.
    for (size_t k = 0; k < gradientCenters.size(); ++k) {
        const Vec3 d = x - gradientCenters[k];
        sum -= 3.0 * d.norm() * gradientWeights[k].dot(d);
    }
    return sum;
}

double VariationalField::valueAndGradient(const Vec3& x, Vec3& gradient) const {
    double sum = constant + linear.dot(x);
    Vec3 g = linear;
    for (size_t i = 0; i < centers.size(); ++i) {
        const Vec3 d = x - centers[i];
        const double r = d.norm();
        sum += weights[i] * r * r * r;
        g += (3.0 * weights[i] * r) * d;
    }
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
// Bounds over a box of half-diagonal h around x0 of the gradient's change
// rate: ||D^2 f|| <= sum_i |w_i| 6 r_i,max + sum_k 12 |b_k|.
double hessianBound(const VariationalField& f, const Box3& box) {
    double bound = 0.0;
    for (size_t i = 0; i < f.centers.size(); ++i) bound += 6.0 * std::abs(f.weights[i]) * box.distanceRange(f.centers[i]).hi;
    for (const Vec3& b : f.gradientWeights) bound += 12.0 * b.norm();
    return bound;
}
}  // namespace

Interval VariationalField::range(const Box3& box) const {
    const Vec3 x0 = box.center();
    const double h = box.halfDiagonal();
    Vec3 g;
    const double v = valueAndGradient(x0, g);
    const double spread = g.norm() * h + 0.5 * hessianBound(*this, box) * h * h;
    return {v - spread, v + spread};
}

double VariationalField::lipschitz(const Box3& box) const {
    Vec3 g;
    valueAndGradient(box.center(), g);
    return g.norm() + hessianBound(*this, box) * box.halfDiagonal();
}

}  // namespace isotrace::geometry
