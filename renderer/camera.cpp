#include "renderer/camera.h"

#include <cmath>
#include <numbers>

namespace isotrace {

PerspectiveCamera::PerspectiveCamera(const CameraSettings& s, int width, int height)
    : settings_(s), width_(width), height_(height) {
    forward_ = (s.to - s.from).normalized();
    right_ = forward_.cross(s.up).normalized();
    up_ = right_.cross(forward_);
    tanHalfFov_ = std::tan(0.5 * s.verticalFovDegrees * std::numbers::pi / 180.0);
    aspect_ = double(width) / double(height);
    if (settings_.focusDistance <= 0) settings_.focusDistance = (s.to - s.from).norm();
}

Ray PerspectiveCamera::generateRay(double x, double y, const Eigen::Vector2d& lens) const {
    const double sx = (2.0 * x / width_ - 1.0) * tanHalfFov_ * aspect_;
    const double sy = (1.0 - 2.0 * y / height_) * tanHalfFov_;
    const Vec3 direction = (forward_ + sx * right_ + sy * up_).normalized();
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
