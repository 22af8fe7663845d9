// A variational implicit surface: the smoothest function (in the thin-plate
// sense of phi(r) = r^3 in 3D) through its constraints,
//   f(x) = sum_i w_i |x - c_i|^3 - sum_k b_k . grad(|x - c_k|^3) + p0 + p . x,
// fitted by fitVariationalField (rbf_solver.h). The second sum carries the
// exact gradient constraints (Hermite interpolation); it is empty otherwise.
// Negative inside, positive outside, like every field here.
#pragma once

#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/interval.h"
#include "geometry/points_by_axis.h"

namespace isotrace::geometry {

struct VariationalField {
    PointsByAxis centers;                ///< value-constraint positions c_i (by axis, for vectorized sums)
    std::vector<double> weights;         ///< w_i
    std::vector<Vec3> gradientCenters;   ///< gradient-constraint positions c_k
    std::vector<Vec3> gradientWeights;   ///< b_k
    double constant = 0.0;               ///< p0
    Vec3 linear = Vec3::Zero();          ///< p
    /// Where the surface is rendered and polygonized: the constraints' box
    /// grown by a margin. Outside it the field is not guaranteed positive.
    Box3 domain;

    double value(const Vec3& x) const;
    double valueAndGradient(const Vec3& x, Vec3& gradient) const;
    /// Sound over the box: the value and gradient at its centre plus
    /// second-order remainders bounded through |D^2 r^3| <= 6 r and
    /// |D^3 r^3| <= 12 (per unit weight).
    Interval range(const Box3& box) const;
    double lipschitz(const Box3& box) const;
    /// The value at x and a radius around x free of zeros of f, from the
    /// exact value, gradient and Hessian at x and the third-derivative
    /// bound: far longer steps than a box's Lipschitz bound allows, because
    /// the sums at x keep their cancellation.
    double valueAndSafeDistance(const Vec3& x, double& safeDistance) const;
    /// The value at x with what bounds f around it, in one pass over the
    /// terms: |grad f(x)|, a bound on ||D^2 f(x)|| and one on ||D^3 f||
    /// anywhere; over the ball of radius h around x,
    /// |grad f| <= gradientNorm + hessian h + third h^2 / 2.
    struct PointBounds {
        double value, gradientNorm, hessian, third;
    };
    PointBounds boundsAt(const Vec3& x) const;
    Box3 bounds() const { return domain; }
    size_t termCount() const { return centers.size() + 3 * gradientCenters.size(); }
    size_t constraintCount() const { return centers.size() + gradientCenters.size(); }
};

}  // namespace isotrace::geometry
