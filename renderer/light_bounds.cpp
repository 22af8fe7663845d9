#include "renderer/light_bounds.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "renderer/light.h"

namespace isotrace {

namespace {

constexpr double kPi = std::numbers::pi;

double safeSqrt(double x) { return std::sqrt(std::max(0.0, x)); }

// An angle a - b clamped at zero, as its cosine and sine, from the cosines
// and sines of a and b (both in [0, pi]): no trigonometric calls, since
// this runs at every node a sample visits.
struct AngleDifference {
    double cos, sin;
};
AngleDifference clampedDifference(double cosA, double sinA, double cosB, double sinB) {
    if (cosA >= cosB) return {1.0, 0.0};  // a <= b
    return {cosA * cosB + sinA * sinB, sinA * cosB - cosA * sinB};
}

}  // namespace

PreparedLightBounds::PreparedLightBounds(const LightBounds& b)
    : center(b.box.center()),
      halfExtent(0.5 * b.box.extent()),
      axis(b.axis),
      radius(b.box.halfDiagonal()),
      power(b.power),
      cosNormalSpread(b.cosNormalSpread),
      sinNormalSpread(safeSqrt(1 - b.cosNormalSpread * b.cosNormalSpread)),
      cosEmissionSpread(b.cosEmissionSpread),
      twoSided(b.twoSided) {}

double LightBounds::importance(const LightSampleContext& context) const {
    return PreparedLightBounds(*this).importance(context);
}

double PreparedLightBounds::importance(const LightSampleContext& context) const {
    if (!(power > 0)) return 0.0;
    const Vec3 fromLight = context.p - center;
    // Two plane tests first, without square roots: most nodes a sample
    // weighs that give nothing fail one of them. Below the receiver's
    // horizon plane the whole box gives nothing; emitters that all face one
    // way (a level ceiling of quads) light only the half-space in front of
    // the box's foremost point.
    const bool atSurface = !context.n.isZero();
    if (atSurface && !(-context.n.dot(fromLight) + context.n.cwiseAbs().dot(halfExtent) > 0)) return 0.0;
    if (cosNormalSpread >= 1.0 && cosEmissionSpread >= 0.0 && !twoSided &&
        !(axis.dot(fromLight) + axis.cwiseAbs().dot(halfExtent) > 0))
        return 0.0;

    const double d2 = fromLight.squaredNorm();
    // Inside the box's bounding sphere every direction is possible.
    if (!(d2 > radius * radius)) return power / std::max(d2, radius * radius);
    // The cone of directions from the context to the bounding sphere:
    // half-angle theta_b.
    const double distance = std::sqrt(d2);
    const double sinB = radius / distance, cosB = safeSqrt(1 - sinB * sinB);
    const Vec3 w = fromLight / distance;

    // theta' = theta_w - theta_o - theta_b: the smallest angle between any
    // normal in the cone and any direction to the context.
    double cosW = axis.dot(w);
    if (twoSided) cosW = std::abs(cosW);
    cosW = std::clamp(cosW, -1.0, 1.0);
    const AngleDifference beyondNormals =
        clampedDifference(cosW, safeSqrt(1 - cosW * cosW), cosNormalSpread, sinNormalSpread);
    const double orientation = clampedDifference(beyondNormals.cos, beyondNormals.sin, cosB, sinB).cos;
    if (!(orientation > cosEmissionSpread)) return 0.0;

    // The receiver's cosine, bounded over the cone to the sphere.
    double receiver = 1.0;
    if (atSurface) {
        const double cosI = std::clamp(-context.n.dot(w), -1.0, 1.0);
        receiver = clampedDifference(cosI, safeSqrt(1 - cosI * cosI), cosB, sinB).cos;
        if (!(receiver > 0)) return 0.0;
    }
    return power * orientation * receiver / d2;
}

double LightBounds::orientationMeasure() const {
    const double thetaO = std::acos(std::clamp(cosNormalSpread, -1.0, 1.0));
    const double thetaE = std::acos(std::clamp(cosEmissionSpread, -1.0, 1.0));
    const double thetaW = std::min(thetaO + thetaE, kPi);
    const double sinO = std::sin(thetaO);
    return 2 * kPi * (1 - cosNormalSpread) +
           kPi / 2 * (2 * thetaW * sinO - std::cos(thetaO - 2 * thetaW) - 2 * thetaO * sinO + cosNormalSpread);
}

LightBounds unite(const LightBounds& first, const LightBounds& second) {
    if (!(first.power > 0)) return second;
    if (!(second.power > 0)) return first;
    LightBounds out;
    out.box = geometry::unionOf(first.box, second.box);
    out.power = first.power + second.power;
    out.twoSided = first.twoSided || second.twoSided;
    out.cosEmissionSpread = std::min(first.cosEmissionSpread, second.cosEmissionSpread);

    // The smallest cone around both cones of normals (a the wider one).
    const bool firstWider = first.cosNormalSpread <= second.cosNormalSpread;
    const LightBounds& a = firstWider ? first : second;
    const LightBounds& b = firstWider ? second : first;
    const double thetaA = std::acos(std::clamp(a.cosNormalSpread, -1.0, 1.0));
    const double thetaB = std::acos(std::clamp(b.cosNormalSpread, -1.0, 1.0));
    const double thetaD = std::acos(std::clamp(a.axis.dot(b.axis), -1.0, 1.0));
    out.axis = a.axis;
    if (std::min(thetaD + thetaB, kPi) <= thetaA) {
        out.cosNormalSpread = a.cosNormalSpread;
        return out;
    }
    // A little wider than exact, so that rounding never leaves a normal out.
    const double theta = 0.5 * (thetaA + thetaD + thetaB) + 1e-9;
    if (theta >= kPi) {
        out.cosNormalSpread = -1.0;
        return out;
    }
    // Turn a's axis towards b's by theta - theta_a.
    Vec3 towards = b.axis - a.axis.dot(b.axis) * a.axis;
    if (!(towards.norm() > 1e-12)) towards = a.axis.unitOrthogonal();
    const double turn = theta - thetaA;
    out.axis = (std::cos(turn) * a.axis + std::sin(turn) * towards.normalized()).normalized();
    out.cosNormalSpread = std::cos(theta);
    return out;
}

LightBounds pointSourceBounds(const Vec3& position, double intensity) {
    LightBounds b;
    b.box = {position, position};
    b.power = intensity;
    b.cosNormalSpread = -1.0;
    b.cosEmissionSpread = 0.0;
    return b;
}

}  // namespace isotrace
