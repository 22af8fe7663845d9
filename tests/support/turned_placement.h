// A leaf placement that doubles a field's size and turns it about a slanted
// axis, with a value scale: what accelerated cells must trace in the leaf's
// frame and bring gradients back from.
#pragma once

#include "geometry/field_program.h"

namespace isotrace::testing {

inline geometry::LeafPlacement turnedPlacement(double angle, const geometry::Vec3& offset, double valueScale) {
    geometry::LeafPlacement placement;
    const geometry::Mat3 rotation =
        Eigen::AngleAxisd(angle, geometry::Vec3(1, 2, 3).normalized()).toRotationMatrix();
    placement.linear = 0.5 * rotation.transpose();  // leaf from world: half the size
    placement.offset = offset;
    placement.valueScale = valueScale;
    placement.gradientScale = 0.5 * valueScale;
    placement.identity = false;
    return placement;
}

}  // namespace isotrace::testing
