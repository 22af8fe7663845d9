// Perspective camera with an optional thin lens.
#pragma once

#include <Eigen/Core>

#include "renderer/ray.h"

namespace isotrace {

struct CameraSettings {
    Vec3 from{0, 1.5, 5};
    Vec3 to{0, 0, 0};
    Vec3 up{0, 1, 0};
    double verticalFovDegrees = 40.0;
    double aperture = 0.0;       ///< lens diameter; 0 is a pinhole
    double focusDistance = 0.0;  ///< 0: the distance from `from` to `to`
};

class PerspectiveCamera {
public:
    PerspectiveCamera(const CameraSettings& settings, int width, int height);

    /// Ray through film position (x, y) in pixels (0,0 is the top-left
    /// corner), using lens sample `lens` in [0,1)^2.
    Ray generateRay(double x, double y, const Eigen::Vector2d& lens) const;
    /// False for a pinhole (aperture 0), which ignores the lens sample.
    bool usesLensSample() const { return settings_.aperture > 0; }
    const CameraSettings& settings() const { return settings_; }

private:
    CameraSettings settings_;
    Vec3 right_, up_, forward_;
    /// Film position to image-plane coordinates (at distance 1, along
    /// right_ and up_): sx = x xScale_ + xOffset_, and the same for y.
    double xScale_, xOffset_, yScale_, yOffset_;
};

}  // namespace isotrace
