// Marching cubes over a field's own bounds at a resolution, with or without
// feature vertices, as the meshing tests start from it.
#pragma once

#include "geometry/meshing/marching_cubes.h"

namespace isotrace::testing {

inline geometry::IndexedMesh marchingCubesMesh(const geometry::FieldProgram& field, int resolution,
                                               bool sharp = false) {
    geometry::MarchingCubesOptions o;
    o.resolution = resolution;
    o.sharpFeatures = sharp;
    return geometry::marchingCubes(field, field.bounds(), o);
}

}  // namespace isotrace::testing
