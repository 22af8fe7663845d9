// The JSON of MPU fields: {"type": "mpu", "points" | "mesh" | "sample" |
// "normals": ..., "accuracy", "support", "max_depth", "min_points"}.
#pragma once

#include <memory>

#include "geometry/description/variational_description.h"
#include "geometry/pointsets/mpu_field.h"

namespace isotrace::geometry {

/// Fits (or finds in the context's cache, by the points' content and the
/// options) the MPU field a description asks for. Errors are InputErrors at
/// the key.
std::shared_ptr<const MpuField> mpuFieldFromDescription(JsonObjectReader& r, VariationalContext& context);

}  // namespace isotrace::geometry
