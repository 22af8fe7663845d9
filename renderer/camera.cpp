#include "renderer/camera.h"

#include <cmath>
#include <numbers>

namespace isotrace {

PerspectiveCamera::PerspectiveCamera(const CameraSettings& s, int width, int height)
    : settings_(s) {
    forward_ = (s.to - s.from).normalized();
    right_ = forward_.cross(s.up).normalized();
    up_ = right_.cross(forward_);
    const double tanHalfFov = std::tan(0.5 * s.verticalFovDegrees * std::numbers::pi / 180.0);
    const double halfWidth = tanHalfFov * double(width) / double(height);
    xScale_ = 2.0 * halfWidth / width;
    xOffset_ = -halfWidth;
    yScale_ = -2.0 * tanHalfFov / height;
    yOffset_ = tanHalfFov;
    if (settings_.focusDistance <= 0) settings_.focusDistance = (s.to - s.from).norm();
}

Ray PerspectiveCamera::generateRay(double x, double y, const Eigen::Vector2d& lens) const {
    // Multiplications by constants and one division: the three divisions
    // here and three more in normalising were a twentieth of a 1-spp
    // Whitted frame.
    const double sx = x * xScale_ + xOffset_, sy = y * yScale_ + yOffset_;
    const Vec3 toPlane = forward_ + sx * right_ + sy * up_;
    const Vec3 direction = toPlane * (1.0 / toPlane.norm());
    if (settings_.aperture <= 0) return {settings_.from, direction};
    // Thin lens: all rays through the same film point meet on the focal plane.
    const double r = 0.5 * settings_.aperture * std::sqrt(lens.x());
    const double phi = 2.0 * std::numbers::pi * lens.y();
    const Vec3 lensPoint = settings_.from + r * (std::cos(phi) * right_ + std::sin(phi) * up_);
    const double tFocus = settings_.focusDistance / direction.dot(forward_);
    const Vec3 focus = settings_.from + tFocus * direction;
    return {lensPoint, (focus - lensPoint).normalized()};
}

}  // namespace isotrace
