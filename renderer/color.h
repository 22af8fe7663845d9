// Linear Rec.709 RGB radiance and reflectance.
#pragma once

#include <Eigen/Core>

namespace isotrace {

using RGB = Eigen::Array3d;

inline double luminance(const RGB& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

}  // namespace isotrace
