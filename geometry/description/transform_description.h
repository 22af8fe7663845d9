// The "translate / rotate / scale" keys shared by field transforms and
// object transforms: scale first, then rotate (axis, angle in degrees),
// then translate.
#pragma once

#include "geometry/description/json_reader.h"

namespace isotrace::geometry {

struct AffineDescription {
    Mat3 linear = Mat3::Identity();
    Vec3 translation = Vec3::Zero();
};

/// Reads `scale` (number or [x, y, z], each > 0), `rotate` {axis, angle}
/// and `translate` from `reader`; absent keys mean identity.
AffineDescription readScaleRotateTranslate(JsonObjectReader& reader);

}  // namespace isotrace::geometry
