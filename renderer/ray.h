// A ray in world space.
#pragma once

#include "geometry/vector_types.h"

namespace isotrace {

using geometry::Vec3;

struct Ray {
    Vec3 origin;
    Vec3 direction;  ///< unit length
};

}  // namespace isotrace
