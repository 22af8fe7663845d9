// Triangle meshes as the geometry library produces them (polygonization):
// shared vertices with unit normals from the field's gradient.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/vector_types.h"

namespace isotrace::geometry {

struct IndexedMesh {
    std::vector<Vec3> vertices;
    std::vector<Vec3> normals;  ///< one per vertex, unit length (may be empty)
    std::vector<std::array<uint32_t, 3>> triangles;
};

}  // namespace isotrace::geometry
