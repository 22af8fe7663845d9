#include "renderer/pixel_filter.h"

#include <cmath>
#include <numbers>

namespace isotrace {

namespace {

// Inverse error function by Newton's method from below: erf is concave on
// x > 0, so iterates starting at y * sqrt(pi) / 2 rise monotonically to the root.
double inverseErf(double y) {
    const double sign = y < 0 ? -1.0 : 1.0;
    y = std::abs(y);
    double x = y * std::sqrt(std::numbers::pi) / 2.0;
    for (int i = 0; i < 30; ++i) {
        const double step = (std::erf(x) - y) / (2.0 / std::sqrt(std::numbers::pi) * std::exp(-x * x));
        x -= step;
        if (std::abs(step) < 1e-14 * std::max(1.0, x)) break;
    }
    return sign * x;
}

// Sample of a normal distribution truncated to [-radius, radius].
double sampleTruncatedGaussian(double u, double sigma, double radius) {
    const double scale = sigma * std::sqrt(2.0);
    const double e = std::erf(radius / scale);
    return scale * inverseErf((2.0 * u - 1.0) * e);
}

}  // namespace

Eigen::Vector2d PixelFilter::sampleOffset(const Eigen::Vector2d& u) const {
    if (type == FilterType::Box) return {(2.0 * u.x() - 1.0) * radius, (2.0 * u.y() - 1.0) * radius};
    return {sampleTruncatedGaussian(u.x(), sigma, radius), sampleTruncatedGaussian(u.y(), sigma, radius)};
}

}  // namespace isotrace
