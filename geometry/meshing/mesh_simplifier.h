// Error-bounded simplification: the adaptive half of polygonization.
//
// Edge collapses ordered by quadric error (Garland and Heckbert; to within
// about 6%, see CostBuckets), each kept only if (1) the link condition
// holds, so the mesh stays 2-manifold and keeps its genus, (2) no face
// turns over, and (3) the new vertex and the centroids of the new faces lie
// within `maxDistance` of the surface, measured on the field itself
// (|f| / |grad f|). New vertices are placed at
// the quadric minimum and projected onto the surface along the gradient, so
// flat regions coarsen while edges and corners (where quadrics are sharp)
// stay.
//
// Collapses run in parallel over blocks of space first: a block collapses an
// edge only when every face around it lies inside the block, so blocks never
// touch the same faces and the result does not depend on the thread count.
// The edges a block had to leave (those near its walls) are then collapsed
// by one queue over the whole mesh.
#pragma once

#include <cstddef>

#include "geometry/field_program.h"
#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

struct SimplifyOptions {
    double maxDistance = 1e-3;
    double minFaceNormalCosine = 0.3;  ///< a face may turn by at most ~72 degrees
    double maxAspectRatio = 30.0;      ///< refuse collapses that create slivers
    int threads = 0;                   ///< 0: all cores
};

/// Simplifies in place; returns the number of collapses.
size_t simplifyMesh(IndexedMesh& mesh, const FieldProgram& field, const SimplifyOptions& options);

}  // namespace isotrace::geometry
