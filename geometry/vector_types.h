// Vector and matrix types shared by the geometry library and its hosts.
// Eigen's fixed-size types live on the stack: no allocation in hot paths.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace isotrace::geometry {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;

}  // namespace isotrace::geometry
