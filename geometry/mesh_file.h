// Reading triangle meshes from files (OBJ, OFF, PLY and whatever else
// Assimp reads): polygons become fans, points and lines are dropped.
#pragma once

#include <string>

#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

/// Vertices and triangles of every mesh in the file, without normals.
/// Missing or unreadable files, non-finite coordinates, out-of-range indices
/// and files without triangles throw InputError naming the file and place.
IndexedMesh readMeshFile(const std::string& path);

/// Area-weighted vertex normals (unit; (0, 1, 0) where the faces around a
/// vertex cancel).
std::vector<Vec3> areaWeightedVertexNormals(const IndexedMesh& mesh);

}  // namespace isotrace::geometry
