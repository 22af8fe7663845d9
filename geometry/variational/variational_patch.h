// A local model of a variational field over one box, cheap to evaluate and
// with a proven error bound: what lets a sphere-tracing step cost O(1)
// instead of O(N).
//
// Inside the box, f = T + sum over near centres + e, where
//  - T is the fourth-order Taylor polynomial, at the box centre, of the
//    terms whose centres lie at least kNearFactor half-diagonals away. Its
//    coefficients are exact sums over all those terms, so the cancellation
//    between the fit's huge, oscillating weights stays inside them.
//  - the near centres (a handful) enter T to second order only, and the
//    rest of each is evaluated exactly (their third derivative jumps at
//    the centre, so no polynomial follows them further);
//  - |e| <= valueError, |grad e| <= gradientError and ||D^2 e|| <=
//    hessianError everywhere in the box.
//    They come from the fifth directional derivative of r^3,
//    |d^5/dt^5 |x + t u|^3| = 45 |a| (1 - a^2)^2 / r^2 <= 12.88 / r^2, summed
//    with |w_j| over the far terms: the terms are bounded one by one, but only
//    at fifth order, where (s / r)^5 makes the sum of |w_j| harmless.
// By Banach's theorem on symmetric forms, the same constant bounds the mixed
// fifth derivatives that the gradient's and Hessian's remainders need.
//
// Hermite (gradient) constraints add terms psi = 3 |d| (b.d), d = x - c
// (b the negated gradient weight). Far ones enter the polynomial to fourth
// order like the others: with s = b.d linear, d^a psi = 3 (s d^a r +
// sum_i a_i b_i d^(a - e_i) r), and along a line |D^5 r| <= 9.882 / r^4 and
// |D^4 r| <= 3 / r^3 give |D^5 psi| <= 3 (9.882 + 15) |b| / r^3. Near ones
// (psi is only C^1 at its centre) enter to first order, the rest evaluated
// exactly: |D^2 psi| <= 9 |b| bounds it by 4.5 |b| |h|^2.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "geometry/variational/variational_field.h"

namespace isotrace::geometry {

/// A term w |x - c|^3 whose centre is too near the box for a Taylor
/// polynomial: its quadratic part is in the polynomial, the rest is
/// evaluated exactly.
struct NearTerm {
    Vec3 center;
    double weight;
    double distance;         ///< from the expansion point
    double inverseDistance;  ///< 0 when the centre is the expansion point
};

/// A Hermite term 3 |x - c| (b.(x - c)) near the box: its value and
/// gradient at the expansion point are in the polynomial, the rest is
/// evaluated exactly.
struct HermiteNearTerm {
    Vec3 center;
    Vec3 direction;         ///< b, the negated gradient weight
    double valueAtExpansion;
    Vec3 gradientAtExpansion;
};

struct VariationalPatch {
    /// Monomials h_x^a h_y^b h_z^c with a + b + c <= 4, h = x - expansionPoint.
    static constexpr int kMonomials = 35;

    Box3 box;
    Vec3 expansionPoint;
    std::array<double, kMonomials> coefficients{};
    std::vector<NearTerm> near;
    std::vector<HermiteNearTerm> nearHermite;
    double valueError = 0.0;     ///< |f - model| over the box
    double gradientError = 0.0;  ///< |grad f - grad model| over the box
    double hessianError = 0.0;   ///< ||D^2 f - D^2 model|| over the box
    /// What the value and gradient errors are made of, so that they can be
    /// told nearer the expansion point, where Taylor's remainder is far
    /// smaller: the far terms' fifth-derivative bound over the box and over
    /// the ball of half its half-diagonal, the coefficients' rounding, and
    /// the box's half-diagonal.
    double fifthDerivative = 0.0, innerFifthDerivative = 0.0, coefficientRounding = 0.0, halfDiagonal = 0.0;
    /// Rounding in evaluating the model (included in valueError; the tracer
    /// adds it to the bounds it derives from the other two).
    double evaluationNoise = 0.0;
    double lipschitz = 0.0;      ///< |grad f| over the box
    /// ||D^2 model|| over the box (the model's, not f's: with the model's
    /// slope at a point it bounds the model along a ray by a parabola).
    double curvature = 0.0;
    /// Rounding in evaluating the model's gradient.
    double gradientNoise = 0.0;
    Interval range;              ///< of f over the box
    /// The model's linear part at the expansion point, value + planeSlope .
    /// (x - expansionPoint), and how far f may stray from it in the box:
    /// rays that stay farther from that plane (in value) meet no surface.
    Vec3 planeSlope = Vec3::Zero();
    double planeBand = 0.0;
    /// |f| > 0 everywhere in the box (the model at the centre minus the
    /// gradient bound times the half-diagonal and the error): rays skip it.
    bool holdsNoZero = false;

    /// Terms the model evaluates exactly at every point.
    size_t nearTermCount() const { return near.size() + nearHermite.size(); }

    /// The model (polynomial plus near terms) and its gradient.
    double value(const Vec3& x) const;
    double valueAndGradient(const Vec3& x, Vec3& gradient) const;
    /// f's range over a box inside this one: the model at its centre, moved
    /// by at most its gradient there times the reach plus half its curvature
    /// times the reach squared (or the gradient bound times the reach), and
    /// the value error.
    Interval rangeOver(const Box3& part) const;
    /// The model and its derivative along `direction` (grad . direction).
    double valueAndSlope(const Vec3& x, const Vec3& direction, double& slope) const;
    /// |f - model| and |grad f - grad model| at points within `reach` of the
    /// expansion point: Taylor's remainder falls as reach^5 (reach^4 for the
    /// gradient), the rounding stays.
    double valueErrorWithin(double reach) const;
    double gradientErrorWithin(double reach) const;

private:
    /// The fifth-derivative bound that holds within `reach` (< halfDiagonal).
    double fifthDerivativeWithin(double reach) const;
};

/// Centres closer to the box centre than this many half-diagonals are near
/// terms; farther ones enter the polynomial, their remainder weighted by
/// 1 / (r - s)^2 (measured on the hand: 1.5 keeps both the near count and
/// the gradient bound low).
constexpr double kNearFactor = 1.5;
/// The same for Hermite terms, whose remainder falls only as 1 / (r - s)^3:
/// at 1.5 the nearest far ones dominate the error (bench/variational_render
/// on the hand's Hermite fit decides it; bench/RESULTS.md).
constexpr double kHermiteNearFactor = 2.0;

/// The model of `field` over `box` (none for an empty or infinite box).
std::optional<VariationalPatch> buildVariationalPatch(const VariationalField& field, const Box3& box);

/// The models of a box split as an octree until every leaf's model is
/// exact to the tolerance asked for, proves its leaf free of surface, or the
/// depth limit is reached: the leaves' models that may hold surface (each
/// with its own box).
std::optional<std::vector<VariationalPatch>> buildSurfaceModels(const VariationalField& field, const Box3& box,
                                                               double tolerance, int maxDepth = 3);

}  // namespace isotrace::geometry
