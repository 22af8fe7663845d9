// Values that several parts of a scene file share the form of: colours and
// object transforms.
#pragma once

#include <string>

#include "geometry/description/json_reader.h"
#include "geometry/vector_types.h"
#include "renderer/color.h"

namespace isotrace {

/// An RGB triple at `key`, or `fallback` when absent; negative components
/// fail unless allowed.
RGB readColor(geometry::JsonObjectReader& r, const std::string& key, const RGB& fallback, bool nonNegative = true);

/// A transform object: "matrix" (4x4 affine) or translate/rotate/scale.
/// Singular transforms fail. Finishes the reader.
geometry::Mat4 readTransform(geometry::JsonObjectReader& r);

}  // namespace isotrace
