#include "geometry/fields/convolution.h"

#include <cmath>
#include <numbers>
#include <unsupported/Eigen/AutoDiff>

namespace isotrace::geometry {

namespace {

// Closed-form integral of the normalised Cauchy kernel along one segment.
// With s = 1/R, x the projection of p on the segment's axis and rho the
// distance to that axis, q^2 = 1 + s^2 rho^2:
//   int dtau / (q^2 + s^2 tau^2)^2 = tau / (2 q^2 (q^2 + s^2 tau^2)) + atan(s tau / q) / (2 q^3 s)
template <class Scalar>
Scalar segmentIntegral(const Eigen::Matrix<Scalar, 3, 1>& p, const ConvolutionSegment& seg) {
    using std::atan2;
    using std::sqrt;
    const Vec3 axis = seg.b - seg.a;
    const double length = axis.norm();
    const Vec3 u = axis / length;
    const Eigen::Matrix<Scalar, 3, 1> d = p - seg.a.cast<Scalar>();
    const Scalar x = d.dot(u.cast<Scalar>());
    const double s = 1.0 / seg.radius;
    Scalar rho2 = d.squaredNorm() - x * x;
    if (rho2 < 0.0) rho2 = rho2 * 0.0;  // round-off below the axis
    const Scalar q2 = 1.0 + s * s * rho2;
    const Scalar q = sqrt(q2);
    auto antiderivative = [&](const Scalar& tau) -> Scalar {  // a Scalar, not a dangling expression template
        return tau / (2.0 * q2 * (q2 + s * s * tau * tau)) + atan2(s * tau, q) / (2.0 * q2 * q * s);
    };
    const Scalar integral = antiderivative(length - x) - antiderivative(-x);
    return integral * (2.0 * s / std::numbers::pi);
}

double kernel(double r, double radius) {
    const double t = 1.0 + (r * r) / (radius * radius);
    return 1.0 / (t * t);
}

// Largest |h'(r)| over [r0, r1]; |h'| peaks at r = R / sqrt(5).
double maxKernelSlope(double r0, double r1, double radius) {
    auto slope = [&](double r) {
        const double t = 1.0 + (r * r) / (radius * radius);
        return 4.0 * r / (radius * radius * t * t * t);
    };
    const double peak = radius / std::sqrt(5.0);
    if (r0 <= peak && peak <= r1) return slope(peak);
    return std::max(slope(r0), slope(r1));
}

// Smallest and largest distance between a box and a segment: bounded by
// sampling-free geometry (the box's distance range to the segment's
// bounding sphere).
Interval segmentBoxDistance(const Box3& box, const ConvolutionSegment& seg) {
    const Vec3 mid = 0.5 * (seg.a + seg.b);
    const double half = 0.5 * (seg.b - seg.a).norm();
    const Interval d = box.distanceRange(mid);
    return {std::max(0.0, d.lo - half), d.hi + half};
}

}  // namespace

double ConvolutionField::value(const Vec3& p) const {
    double sum = 0.0;
    for (const ConvolutionSegment& s : segments) sum += s.weight * segmentIntegral<double>(p, s);
    return threshold - sum;
}

double ConvolutionField::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    using Dual = Eigen::AutoDiffScalar<Eigen::Vector3d>;
    Eigen::Matrix<Dual, 3, 1> x;
    for (int i = 0; i < 3; ++i) x[i] = Dual(p[i], 3, i);
    double sum = 0.0;
    gradient = Vec3::Zero();
    for (const ConvolutionSegment& s : segments) {
        const Dual v = segmentIntegral<Dual>(x, s);
        sum += s.weight * v.value();
        gradient -= s.weight * v.derivatives();
    }
    return threshold - sum;
}

Interval ConvolutionField::range(const Box3& box) const {
    // Each normalised integral lies between length * h(dmax) and
    // length * h(dmin) (times 2/(pi R)), and is at most 1.
    Interval sum(0.0);
    for (const ConvolutionSegment& s : segments) {
        const Interval d = segmentBoxDistance(box, s);
        const double length = (s.b - s.a).norm();
        const double scale = 2.0 / (std::numbers::pi * s.radius);
        const double lo = scale * length * kernel(d.hi, s.radius);
        const double hi = std::min(1.0, scale * length * kernel(d.lo, s.radius));
        sum += s.weight * Interval(std::min(lo, hi), hi);
    }
    return Interval(threshold) - sum;
}

double ConvolutionField::lipschitz(const Box3& box) const {
    // |grad F| <= integral of |h'| along the segment <= length * max |h'|.
    double sum = 0.0;
    for (const ConvolutionSegment& s : segments) {
        const Interval d = segmentBoxDistance(box, s);
        const double length = (s.b - s.a).norm();
        const double scale = 2.0 / (std::numbers::pi * s.radius);
        sum += std::abs(s.weight) * scale * length * maxKernelSlope(d.lo, d.hi, s.radius);
    }
    return sum;
}

Box3 ConvolutionField::bounds() const {
    // Outside distance rho of every segment, each term is at most
    // scale * length * h(rho); choose rho so the positive terms sum to T.
    if (threshold <= 0) return Box3::everything();
    double total = 0.0;
    for (const ConvolutionSegment& s : segments)
        if (s.weight > 0) total += s.weight * (2.0 / (std::numbers::pi * s.radius)) * (s.b - s.a).norm();
    Box3 box;
    if (total <= threshold) return box;  // nothing can reach the threshold
    const double eta = threshold / total;  // h(rho) <= eta  <=>  rho >= R sqrt(1/sqrt(eta) - 1)
    for (const ConvolutionSegment& s : segments) {
        if (s.weight <= 0) continue;
        const double rho = s.radius * std::sqrt(std::max(0.0, 1.0 / std::sqrt(eta) - 1.0));
        Box3 b;
        b.extend(s.a);
        b.extend(s.b);
        box.extend(b.expanded(rho));
    }
    return box;
}

}  // namespace isotrace::geometry
