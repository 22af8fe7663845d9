// Error-driven refinement: the first half of adaptive polygonization, which
// extracts on a coarser grid than the accuracy asks for and refines only
// where the surface needs it (Velho's adaptive polygonization).
//
// Every face whose centroid lies farther than `maxDistance` from the surface
// (|f| / |grad f|) is bisected at its longest edge and the new vertex is
// projected onto the surface by Newton steps along the gradient. Bisection
// follows Rivara's longest-edge propagation path: an edge is split only when
// it is the longest edge of the faces on both sides (the neighbour is split
// first when it is not), so the mesh stays conforming (watertight and
// 2-manifold, with the same genus) and no angle falls below half of the
// smallest one it started with.
//
// Larger meshes are refined in blocks of space at once, each splitting only
// faces whose vertices all lie in it, then along the blocks' walls; the new
// faces and vertices are numbered block by block, so the result does not
// depend on the number of threads.
#pragma once

#include <cstddef>

#include "geometry/field_program.h"
#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

struct RefineOptions {
    double maxDistance = 1e-3;
    /// Faces whose longest edge is shorter are left as they are (where the
    /// field is not smooth, halving may not bring a face nearer).
    double minEdgeLength = 0.0;
    int threads = 0;  ///< 0: all cores
};

struct RefineStatistics {
    size_t splits = 0;
    /// Faces still farther than maxDistance at the end: their edges reached
    /// minEdgeLength, or a split near them was refused.
    size_t facesBeyond = 0;
    /// Splits refused because Newton could not bring the new vertex within
    /// maxDistance of the surface: the field is not smooth there, or its
    /// gradient nearly vanishes (and |f| / |grad f| is no distance). The
    /// edge's faces are then not refined again.
    size_t refusedSplits = 0;
};

/// Refines in place. The mesh's normals, when it has them, are extended with
/// the field's for the new vertices.
RefineStatistics refineMesh(IndexedMesh& mesh, const FieldProgram& field, const RefineOptions& options);

}  // namespace isotrace::geometry
