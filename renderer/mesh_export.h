// Writing polygonized meshes: binary PLY and OBJ through Assimp, OFF by
// hand (Assimp has no OFF exporter; the format is three header lines).
// Files appear only when complete (temporary name, then rename).
#pragma once

#include <string>

#include "geometry/indexed_mesh.h"

namespace isotrace {

/// The format follows the extension: .ply, .obj or .off. Throws
/// std::runtime_error naming the path on failure or an unknown extension.
void writeMesh(const std::string& path, const geometry::IndexedMesh& mesh);

/// True for the extensions writeMesh knows.
bool isMeshExtension(const std::string& path);

}  // namespace isotrace
