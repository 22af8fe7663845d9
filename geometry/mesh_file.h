// Reading triangle meshes from files (OBJ, OFF, PLY and whatever else
// Assimp reads): polygons become fans, points and lines are dropped.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

/// A path's extension in lower case, with its dot (".ply"): what file
/// formats are chosen by.
std::string lowercaseExtension(const std::string& path);

/// Vertices and triangles of every mesh in the file, without normals; with
/// `uvs`, also the texture coordinates (u, v) of every vertex, or none when
/// a part of the file has none. Missing or unreadable files, non-finite
/// coordinates, out-of-range indices and files without triangles throw
/// InputError naming the file and place.
IndexedMesh readMeshFile(const std::string& path, std::vector<std::array<float, 2>>* uvs = nullptr);

struct MeshRepair {
    size_t weldedVertices = 0;   ///< vertices merged into one at the same place
    size_t droppedTriangles = 0; ///< triangles left with zero area or a repeated vertex
};

/// Real models repeat vertices (UV seams, split normals) and carry slivers.
/// Merges vertices closer than `relativeTolerance` times the bounding box's
/// diagonal (the first of them keeps its index), then drops triangles that
/// became degenerate. Unused vertices stay (they carry no surface).
MeshRepair weldCoincidentVertices(IndexedMesh& mesh, double relativeTolerance = 1e-7);

/// Area-weighted vertex normals (unit; (0, 1, 0) where the faces around a
/// vertex cancel).
std::vector<Vec3> areaWeightedVertexNormals(const IndexedMesh& mesh);

}  // namespace isotrace::geometry
