// Marching cubes on a uniform grid over a box, visiting only the cells whose
// value range can contain zero (an interval octree descends to bricks of
// 8^3 cells), so the cost grows with the surface's area, not the volume.
//
// Topology: each cube face with four crossings is resolved by the asymptotic
// decider on that face's bilinear interpolant. The decision depends on the
// face's corner values alone, so the two cubes sharing a face agree, and the
// contour of each cube is a set of closed loops: the mesh is watertight and
// 2-manifold wherever the surface is closed inside the box. Triangles are
// oriented with outward (gradient-facing) normals.
//
// Vertices lie on the surface: each edge crossing is refined by safeguarded
// secant steps on the field itself; normals are the normalised gradient.
// With `sharpFeatures`, a loop whose normals disagree strongly gets a vertex
// placed by a quadric error function (the least-squares meeting point of the
// tangent planes, kept inside its cell), and the loop is fanned around it:
// edges and corners of CSG solids survive (Kobbelt et al.'s extended MC).
#pragma once

#include "geometry/bounding_box.h"
#include "geometry/field_program.h"
#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

struct MarchingCubesOptions {
    int resolution = 128;        ///< cells along the box's longest side
    bool sharpFeatures = false;  ///< quadric-placed feature vertices
    double featureAngleDegrees = 30.0;
    int threads = 0;             ///< 0: all cores
};

struct MarchingCubesStatistics {
    long long cellsVisited = 0;  ///< cells whose corners were evaluated
    long long bricksVisited = 0;
    long long fieldEvaluations = 0;
};

/// Cells are cubes of side longest(box) / resolution; the grid covers `box`.
IndexedMesh marchingCubes(const FieldProgram& field, const Box3& box, const MarchingCubesOptions& options,
                          MarchingCubesStatistics* statistics = nullptr);

}  // namespace isotrace::geometry
