// Polygonization of any bounded field: the entry point that chooses between
// uniform marching cubes and the adaptive mesher (marching cubes with
// feature vertices on half the grid, error-driven refinement, then
// error-bounded simplification), picks resolutions for a target tolerance,
// and refuses requests that cannot fit in memory.
#pragma once

#include <string>
#include <vector>

#include "geometry/field_program.h"
#include "geometry/indexed_mesh.h"
#include "geometry/meshing/marching_cubes.h"

namespace isotrace::geometry {

enum class PolygonizeMethod { MarchingCubes, Adaptive };

struct PolygonizeOptions {
    PolygonizeMethod method = PolygonizeMethod::MarchingCubes;
    int resolution = 0;      ///< cells along the longest side; 0: 128, or chosen for `tolerance`
    /// Largest distance of vertices and face centroids to the surface; 0:
    /// none for marching cubes, and for the adaptive mesher what marching
    /// cubes reaches on the grid (extracting there, not on half of it).
    double tolerance = 0.0;
    int threads = 0;
};

struct Polygonization {
    IndexedMesh mesh;
    int resolution = 0;            ///< the grid given, or for a tolerance the one marching cubes used
    /// Of the marching-cubes grid used: half the resolution for the adaptive
    /// mesher given a tolerance.
    int extractionResolution = 0;
    double seconds = 0.0;
    /// The stages: marching cubes (with the search for a grid), and for the
    /// adaptive mesher refinement and simplification.
    double extractionSeconds = 0.0, refinementSeconds = 0.0, simplificationSeconds = 0.0;
    std::vector<std::string> warnings;
};

/// Highest resolution accepted, and the memory estimate behind refusals.
constexpr int kMaxPolygonizeResolution = 8192;
double estimatePolygonizeBytes(int resolution);

/// Throws std::invalid_argument (a message for users) for an unbounded
/// field, a resolution that is not positive, or one too large for memory.
Polygonization polygonize(const FieldProgram& field, const PolygonizeOptions& options);

}  // namespace isotrace::geometry
