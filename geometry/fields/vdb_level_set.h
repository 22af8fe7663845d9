// A level set read from an OpenVDB file, as a field: the trilinear
// interpolant of its voxels (OpenVDB's own BoxSampler reconstruction), in
// world units, negative inside.
//
// Its bounds are proven from the voxels: per block of 8^3 cells the range
// and largest gradient of the interpolant (openvdb_library.h), gathered in
// a pyramid so that any box is answered from at most 8 entries. Beyond the
// stored voxels the field is the grid's background, a constant that no
// surface crosses.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/interval.h"
#include "geometry/openvdb_library.h"

namespace isotrace::geometry {

class VdbLevelSet {
public:
    explicit VdbLevelSet(LevelSetGridData grid);

    double value(const Vec3& p) const;
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    Interval range(const Box3& box) const;
    double lipschitz(const Box3& box) const;
    /// The stored voxels' cells, in world space.
    Box3 bounds() const { return bounds_; }

    /// Index space: voxel centres at integer points, cell (i, j, k) the unit
    /// cube above voxel (i, j, k). Rays keep their t there (the map is affine).
    Vec3 indexOf(const Vec3& p) const { return worldToIndex_ * p + worldToIndexOffset_; }
    Vec3 indexDirectionOf(const Vec3& d) const { return worldToIndex_ * d; }
    /// The corners of an index cell (corner (a, b, c) at a + 2b + 4c); the
    /// background outside the stored blocks.
    void cellCorners(const Eigen::Vector3i& cell, float corners[8]) const;
    /// The footprint of the block holding a cell (its 9^3 voxels, x
    /// fastest), and the cell's offset in it; null where the block's range
    /// holds no zero (no surface crosses it) or the cell lies beyond the blocks.
    const float* footprintOf(const Eigen::Vector3i& cell, int& offset) const {
        size_t index = 0, stride = 1;
        offset = 0;
        int offsetStride = 1;
        for (int axis = 0; axis < 3; ++axis) {
            const int block = (cell[axis] >= 0 ? cell[axis] : cell[axis] - (kVoxelBlockCells - 1)) / kVoxelBlockCells;
            const int relative = block - grid_.blockOrigin[axis];
            if (relative < 0 || relative >= grid_.blockCount[axis]) return nullptr;
            index += stride * size_t(relative);
            stride *= size_t(grid_.blockCount[axis]);
            offset += offsetStride * (cell[axis] - kVoxelBlockCells * block);
            offsetStride *= kFootprintSide;
        }
        const uint32_t f = grid_.footprintOf[index];
        return f == kNoFootprint ? nullptr : grid_.footprints.data() + size_t(f) * kFootprintVoxels;
    }
    /// The corners of a cell of a footprint, at `offset`.
    static void footprintCorners(const float* footprint, int offset, float corners[8]) {
        constexpr int dy = kFootprintSide, dz = kFootprintSide * kFootprintSide;
        const float* v = footprint + offset;
        corners[0] = v[0], corners[1] = v[1], corners[2] = v[dy], corners[3] = v[dy + 1];
        corners[4] = v[dz], corners[5] = v[dz + 1], corners[6] = v[dz + dy], corners[7] = v[dz + dy + 1];
    }

    double voxelSize() const { return grid_.voxelSize; }
    double background() const { return grid_.background; }
    const LevelSetGridData& grid() const { return grid_; }

private:
    /// The blocks [lo, hi] (inclusive, per axis, relative to the block
    /// origin) whose cells a world box reaches; `outside` when it reaches
    /// cells beyond them.
    struct BlockSpan {
        int lo[3], hi[3];
        bool outside = false;
        bool empty = false;
    };
    BlockSpan blocksOf(const Box3& box) const;
    /// The bounds over every block of a span, from the coarsest pyramid
    /// level that covers it with at most two entries per axis.
    VoxelBlockBounds gather(const BlockSpan& span) const;

    LevelSetGridData grid_;
    Mat3 worldToIndex_, worldToIndexAbs_;
    Vec3 worldToIndexOffset_;
    Box3 bounds_;
    /// Level k holds the bounds of 2^k x 2^k x 2^k blocks; level 0 is
    /// grid_.blocks.
    struct Level {
        int count[3];
        std::vector<VoxelBlockBounds> entries;
    };
    std::vector<Level> levels_;
};

/// The field kind: shared, since every octree cell's pruned program holds one.
struct VdbLevelSetField {
    std::shared_ptr<const VdbLevelSet> levelSet;

    double value(const Vec3& p) const { return levelSet->value(p); }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const { return levelSet->valueAndGradient(p, gradient); }
    Interval range(const Box3& box) const { return levelSet->range(box); }
    double lipschitz(const Box3& box) const { return levelSet->lipschitz(box); }
    Box3 bounds() const { return levelSet->bounds(); }
};

}  // namespace isotrace::geometry
