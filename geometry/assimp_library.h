// Polygon model files through Assimp, behind an interface whose
// implementation lives in a module of its own (isotrace_assimp.so), loaded
// on first use: linked in, Assimp (and Draco, which it pulls in) would slow
// the start of every process, and a scene without meshes need not pay for
// it (bench/RESULTS.md, "Portable build").
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

/// What Assimp read from a file, unchecked: each mesh's vertices and its
/// faces as index lists (polygons, lines and points as they are).
struct MeshFileContents {
    struct Part {
        std::vector<Vec3> vertices;
        /// The first texture coordinates (u, v) per vertex, or empty.
        std::vector<std::array<float, 2>> uvs;
        std::vector<uint32_t> faceSizes;  ///< indices per face
        std::vector<uint32_t> indices;    ///< every face's indices, in order
    };
    std::vector<Part> parts;
};

class AssimpLibrary {
public:
    virtual ~AssimpLibrary() = default;
    /// Every mesh in the file, without post-processing. Throws
    /// std::runtime_error with Assimp's message when it cannot read it.
    virtual MeshFileContents read(const std::string& path) = 0;
    /// Writes one triangle mesh (and its normals, if it has them) in
    /// Assimp's export format `formatId` ("plyb", "objnomtl"). Throws
    /// std::runtime_error with Assimp's message.
    virtual void write(const std::string& path, const IndexedMesh& mesh, const std::string& formatId) = 0;
};

/// The library, loaded on the first call: from $ISOTRACE_ASSIMP_MODULE when
/// set (only there), else beside the executable or in an installed tree's
/// lib/isotrace (see loadable_module.h). Throws std::runtime_error saying
/// where it looked.
AssimpLibrary& assimpLibrary();

}  // namespace isotrace::geometry

/// The module's one entry point (C linkage, so dlsym finds it by name).
extern "C" isotrace::geometry::AssimpLibrary* isotraceAssimpLibrary();
