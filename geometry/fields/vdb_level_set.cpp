#include "geometry/fields/vdb_level_set.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace isotrace::geometry {

namespace {

VoxelBlockBounds merged(const VoxelBlockBounds& a, const VoxelBlockBounds& b) {
    return {std::min(a.lo, b.lo), std::max(a.hi, b.hi), std::max(a.gradient, b.gradient)};
}

}  // namespace

VdbLevelSet::VdbLevelSet(LevelSetGridData grid) : grid_(std::move(grid)) {
    const auto& a = grid_.indexToWorld;
    Mat3 indexToWorld;
    indexToWorld << a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8];
    const Vec3 offset(grid_.indexOffset[0], grid_.indexOffset[1], grid_.indexOffset[2]);
    if (!(grid_.voxelSize > 0) || std::abs(indexToWorld.determinant()) == 0)
        throw std::invalid_argument("the grid's transform is singular");
    worldToIndex_ = indexToWorld.inverse();
    worldToIndexAbs_ = worldToIndex_.cwiseAbs();
    worldToIndexOffset_ = -(worldToIndex_ * offset);
    const size_t expected = size_t(grid_.blockCount[0]) * size_t(grid_.blockCount[1]) * size_t(grid_.blockCount[2]);
    if (grid_.blocks.size() != expected || expected == 0)
        throw std::invalid_argument("the grid's block bounds do not match its block counts");

    // The world box of every cell the blocks hold.
    constexpr int n = kVoxelBlockCells;
    for (int c = 0; c < 8; ++c) {
        Vec3 corner;
        for (int axis = 0; axis < 3; ++axis)
            corner[axis] = n * double(grid_.blockOrigin[axis] + ((c >> axis & 1) ? grid_.blockCount[axis] : 0));
        bounds_.extend(Vec3(indexToWorld * corner + offset));
    }

    Level base;
    for (int axis = 0; axis < 3; ++axis) base.count[axis] = grid_.blockCount[axis];
    base.entries = grid_.blocks;
    levels_.push_back(std::move(base));
    while (levels_.back().count[0] > 1 || levels_.back().count[1] > 1 || levels_.back().count[2] > 1) {
        const Level& fine = levels_.back();
        Level coarse;
        for (int axis = 0; axis < 3; ++axis) coarse.count[axis] = (fine.count[axis] + 1) / 2;
        coarse.entries.assign(size_t(coarse.count[0]) * coarse.count[1] * coarse.count[2],
                              {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), 0.0f});
        for (int z = 0; z < fine.count[2]; ++z)
            for (int y = 0; y < fine.count[1]; ++y)
                for (int x = 0; x < fine.count[0]; ++x) {
                    VoxelBlockBounds& to =
                        coarse.entries[size_t(x / 2) + size_t(coarse.count[0]) * (size_t(y / 2) + size_t(coarse.count[1]) * (z / 2))];
                    to = merged(to, fine.entries[size_t(x) + size_t(fine.count[0]) * (size_t(y) + size_t(fine.count[1]) * z)]);
                }
        levels_.push_back(std::move(coarse));
    }
}

VdbLevelSet::BlockSpan VdbLevelSet::blocksOf(const Box3& box) const {
    BlockSpan span;
    const Vec3 center = indexOf(box.center());
    const Vec3 half = worldToIndexAbs_ * (0.5 * box.extent());
    for (int axis = 0; axis < 3; ++axis) {
        const int count = grid_.blockCount[axis];
        // Cell c spans [c, c + 1]; its block is floor(c / 8). In doubles
        // first: a box far away must not overflow an int.
        double lo = std::floor(std::floor(center[axis] - half[axis]) / kVoxelBlockCells) - grid_.blockOrigin[axis];
        double hi = std::floor(std::floor(center[axis] + half[axis]) / kVoxelBlockCells) - grid_.blockOrigin[axis];
        if (!(lo >= 0)) {  // also NaN
            span.outside = true;
            lo = 0;
        }
        if (!(hi <= count - 1)) {
            span.outside = true;
            hi = count - 1;
        }
        if (lo > hi) span.empty = true;
        span.lo[axis] = int(lo);
        span.hi[axis] = int(hi);
    }
    return span;
}

VoxelBlockBounds VdbLevelSet::gather(const BlockSpan& span) const {
    size_t k = 0;
    auto fits = [&](size_t level) {
        for (int axis = 0; axis < 3; ++axis)
            if ((span.hi[axis] >> level) - (span.lo[axis] >> level) > 1) return false;
        return true;
    };
    while (!fits(k)) ++k;
    const Level& level = levels_[k];
    VoxelBlockBounds out{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), 0.0f};
    for (int z = span.lo[2] >> k; z <= span.hi[2] >> k; ++z)
        for (int y = span.lo[1] >> k; y <= span.hi[1] >> k; ++y)
            for (int x = span.lo[0] >> k; x <= span.hi[0] >> k; ++x)
                out = merged(out, level.entries[size_t(x) + size_t(level.count[0]) * (size_t(y) + size_t(level.count[1]) * z)]);
    return out;
}

Interval VdbLevelSet::range(const Box3& box) const {
    const BlockSpan span = blocksOf(box);
    if (span.empty) return Interval(grid_.background);
    const VoxelBlockBounds b = gather(span);
    Interval out(b.lo, b.hi);
    if (span.outside) out = Interval(std::min<double>(out.lo, grid_.background), std::max<double>(out.hi, grid_.background));
    return out;
}

double VdbLevelSet::lipschitz(const Box3& box) const {
    const BlockSpan span = blocksOf(box);
    if (span.empty) return 0.0;
    // Index units are voxels: a world step of d is d / voxelSize voxels.
    return double(gather(span).gradient) / grid_.voxelSize;
}

double VdbLevelSet::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    const Vec3 x = indexOf(p);
    Vec3 cell;
    for (int axis = 0; axis < 3; ++axis) {
        cell[axis] = std::floor(x[axis]);
        const double first = double(kVoxelBlockCells) * grid_.blockOrigin[axis];
        // Outside the blocks (or not a number) every corner is background.
        if (!(cell[axis] >= first - 1 && cell[axis] <= first + double(kVoxelBlockCells) * grid_.blockCount[axis])) {
            gradient = Vec3::Zero();
            return grid_.background;
        }
    }
    float v[8];
    cellCorners(cell.cast<int>(), v);
    const Vec3 t = x - cell;
    // Trilinear: along x on each of the four x-edges, then y, then z.
    const double e00 = v[0] + t.x() * (v[1] - v[0]), e10 = v[2] + t.x() * (v[3] - v[2]);
    const double e01 = v[4] + t.x() * (v[5] - v[4]), e11 = v[6] + t.x() * (v[7] - v[6]);
    const double f0 = e00 + t.y() * (e10 - e00), f1 = e01 + t.y() * (e11 - e01);
    const double value = f0 + t.z() * (f1 - f0);
    const double d00 = v[1] - v[0], d10 = v[3] - v[2], d01 = v[5] - v[4], d11 = v[7] - v[6];
    const double dx0 = d00 + t.y() * (d10 - d00), dx1 = d01 + t.y() * (d11 - d01);
    const Vec3 indexGradient(dx0 + t.z() * (dx1 - dx0), (1 - t.z()) * (e10 - e00) + t.z() * (e11 - e01), f1 - f0);
    gradient = worldToIndex_.transpose() * indexGradient;
    return value;
}

void VdbLevelSet::cellCorners(const Eigen::Vector3i& cell, float corners[8]) const {
    int offset;
    if (const float* footprint = footprintOf(cell, offset)) return footprintCorners(footprint, offset, corners);
    bool inBlocks = true;
    for (int axis = 0; axis < 3; ++axis) {
        const double first = double(kVoxelBlockCells) * grid_.blockOrigin[axis];
        inBlocks = inBlocks && cell[axis] >= first && cell[axis] < first + double(kVoxelBlockCells) * grid_.blockCount[axis];
    }
    // Beyond the blocks every corner is the background.
    if (!inBlocks) return std::fill(corners, corners + 8, grid_.background);
    grid_.voxels->cellCorners(cell.x(), cell.y(), cell.z(), corners);
}

double VdbLevelSet::value(const Vec3& p) const {
    Vec3 unused;
    return valueAndGradient(p, unused);
}

}  // namespace isotrace::geometry
