// OpenVDB level sets, behind an interface whose implementation lives in a
// module of its own (isotrace_openvdb.so), loaded on first use as Assimp is
// (loadable_module.h): a scene without VDB files does not pay for OpenVDB.
//
// Reading hands back the grid's voxels (for sampling) and, per block of 8^3
// cells, the range and gradient bound of their trilinear interpolant, from
// which fields/vdb_level_set.h proves its bounds. Writing turns a closed
// triangle mesh into a narrow-band signed-distance level set with OpenVDB's
// own mesh-to-volume conversion.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geometry/indexed_mesh.h"

namespace isotrace::geometry {

/// Cells per block along each axis: one OpenVDB leaf node.
constexpr int kVoxelBlockCells = 8;
/// The voxels a block's cells have for corners: 9^3, x fastest.
constexpr int kFootprintSide = kVoxelBlockCells + 1;
constexpr int kFootprintVoxels = kFootprintSide * kFootprintSide * kFootprintSide;
constexpr uint32_t kNoFootprint = 0xffffffffu;

/// What the trilinear interpolant does over one block of cells (its cells'
/// corners are the block's 9^3 voxels): its range, and the largest norm of
/// its gradient, in values per voxel.
struct VoxelBlockBounds {
    float lo = 0.0f, hi = 0.0f;
    float gradient = 0.0f;
};

/// The voxels of a grid, read concurrently.
class LevelSetVoxels {
public:
    virtual ~LevelSetVoxels() = default;
    /// The values at the 8 corners of the cell whose lowest voxel is
    /// (i, j, k), corner (a, b, c) at index a + 2b + 4c.
    virtual void cellCorners(int i, int j, int k, float corners[8]) const = 0;
};

/// A level set as read: voxels, placement and the bounds of its blocks.
struct LevelSetGridData {
    std::shared_ptr<const LevelSetVoxels> voxels;
    /// world = indexToWorld * index + indexOffset, index (0, 0, 0) at a
    /// voxel's centre; a rotation times the voxel size.
    std::array<double, 9> indexToWorld{};  ///< row-major
    std::array<double, 3> indexOffset{};
    double voxelSize = 0.0;
    float background = 0.0f;  ///< the value wherever nothing is stored
    /// Blocks cover cells [8 blockOrigin, 8 (blockOrigin + blockCount));
    /// every cell outside sees only the background.
    std::array<int, 3> blockOrigin{}, blockCount{};
    std::vector<VoxelBlockBounds> blocks;  ///< x fastest, then y, then z
    /// The voxels of every block whose range holds zero (the only blocks a
    /// surface crosses), copied so that tracing reads corners from an array:
    /// footprintOf[block] is the block's place in `footprints`, in units of
    /// kFootprintVoxels, or kNoFootprint.
    std::vector<uint32_t> footprintOf;
    std::vector<float> footprints;
    uint64_t activeVoxels = 0;
    std::map<std::string, std::string> metadata;  ///< the grid's string metadata
};

/// What to write: one grid of a level set or fog volume.
struct LevelSetWriteOptions {
    double voxelSize = 0.0;
    double halfWidth = 3.0;  ///< of the narrow band, in voxels
    std::string gridName = "surface";
    bool fog = false;  ///< density 1 inside, falling to 0 across the inner band
    std::map<std::string, std::string> metadata;  ///< into the grid's and the file's metadata
};

struct LevelSetWriteReport {
    uint64_t activeVoxels = 0;
    uint64_t leafNodes = 0;
    uint64_t fileBytes = 0;
};

class OpenVdbLibrary {
public:
    virtual ~OpenVdbLibrary() = default;
    /// The float level set named `grid` in the file. Throws
    /// std::runtime_error with a message naming the grid (and, for a
    /// missing one, the grids there are): unreadable or corrupt files,
    /// grids that are not float level sets, non-linear transforms,
    /// non-uniform voxels, empty grids, voxels that are not numbers, and
    /// bounds and footprints that would take more than `memoryBudget` bytes.
    virtual LevelSetGridData readLevelSet(const std::string& path, const std::string& grid, double memoryBudget) = 0;
    /// The signed distance to the closed mesh (inside negative) in a narrow
    /// band, as a level set (or a fog volume) written to `path`. Throws
    /// std::runtime_error.
    virtual LevelSetWriteReport writeLevelSet(const std::string& path, const IndexedMesh& mesh,
                                              const LevelSetWriteOptions& options) = 0;
};

/// The library, loaded on the first call: from $ISOTRACE_OPENVDB_MODULE
/// when set, else beside the executable or in an installed tree's
/// lib/isotrace. Throws std::runtime_error saying where it looked.
OpenVdbLibrary& openVdbLibrary();

}  // namespace isotrace::geometry

/// The module's one entry point (C linkage, so dlsym finds it by name).
extern "C" isotrace::geometry::OpenVdbLibrary* isotraceOpenVdbLibrary();
