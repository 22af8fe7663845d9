// Triangle meshes as the renderer holds them: object-space positions in
// single precision (Embree's format), indices, optional vertex normals.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/vector_types.h"

namespace isotrace {

using geometry::Vec3;

struct TriangleMesh {
    std::vector<float> positions;   ///< x y z per vertex
    std::vector<uint32_t> indices;  ///< three per triangle
    std::vector<float> normals;     ///< x y z per vertex, or empty for flat shading
    /// u v per vertex (texture coordinates, v up as in OBJ and Blender), or empty.
    std::vector<float> uvs;

    size_t vertexCount() const { return positions.size() / 3; }
    size_t triangleCount() const { return indices.size() / 3; }
    Vec3 vertex(uint32_t i) const { return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]}; }
    Vec3 normal(uint32_t i) const { return {normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]}; }

    /// Index of the first triangle with zero area or repeated vertices, or -1.
    long firstDegenerateTriangle() const;
    /// Removes degenerate triangles; returns how many.
    size_t dropDegenerateTriangles();
    /// Area-weighted vertex normals, summed over every vertex at the same
    /// place: vertices split only to carry different texture coordinates
    /// (UV seams) get the same normal.
    void computeSmoothNormals();
};

/// Oriented discs (Embree's built-in disc points): how particles on a
/// surface are shown. Object space, single precision.
struct DiscPoints {
    std::vector<float> centersAndRadii;  ///< x y z radius per disc
    std::vector<float> normals;          ///< x y z per disc, unit
    size_t count() const { return centersAndRadii.size() / 4; }
};

/// Loads OBJ, OFF or PLY through Assimp. Throws InputError naming `path`.
TriangleMesh loadTriangleMesh(const std::string& path);

}  // namespace isotrace
