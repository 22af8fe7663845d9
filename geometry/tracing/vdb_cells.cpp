#include "geometry/tracing/vdb_cells.h"

#include <cmath>

#include "geometry/bernstein_root.h"
#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

// The trilinear interpolant of one cell's corners along u(s) = a + s b (u in
// the cell's unit cube), as a cubic in s: interpolated along x, then y, then
// z, each step multiplying by a linear factor.
Monomials<3> trilinearAlongLine(const float v[8], const Vec3& a, const Vec3& b) {
    // Linear factors (1 - u_k) and u_k as [constant, slope].
    auto times = [](const auto& p, double c0, double c1) {
        constexpr int n = std::tuple_size_v<std::decay_t<decltype(p)>>;
        std::array<double, n + 1> q{};
        for (int i = 0; i < n; ++i) {
            q[i] += p[i] * c0;
            q[i + 1] += p[i] * c1;
        }
        return q;
    };
    std::array<std::array<double, 2>, 4> alongX;  // edges (y, z) = index / 1 % 2, / 2
    for (int e = 0; e < 4; ++e) {
        const double v0 = v[2 * e], v1 = v[2 * e + 1];
        alongX[e] = {v0 + a.x() * (v1 - v0), b.x() * (v1 - v0)};
    }
    std::array<std::array<double, 3>, 2> alongY;
    for (int z = 0; z < 2; ++z) {
        const auto low = times(alongX[2 * z], 1 - a.y(), -b.y()), high = times(alongX[2 * z + 1], a.y(), b.y());
        for (int i = 0; i < 3; ++i) alongY[z][i] = low[i] + high[i];
    }
    const auto low = times(alongY[0], 1 - a.z(), -b.z()), high = times(alongY[1], a.z(), b.z());
    return {low[0] + high[0], low[1] + high[1], low[2] + high[2], low[3] + high[3]};
}

// Where a ray is along each axis of a grid of cubes of side `size` (index
// units): the cube holding it at t (stepping the way the ray goes where it
// lies on a face), when it leaves that cube along each axis, and the step.
struct GridWalk {
    Eigen::Vector3i at, step;
    Vec3 next, delta;

    GridWalk(const Vec3& xo, const Vec3& xd, double t, double size) {
        const Vec3 x = xo + t * xd;
        for (int k = 0; k < 3; ++k) {
            double c = std::floor(x[k] / size);
            if (xd[k] < 0 && c * size == x[k]) c -= 1;
            at[k] = int(c);
            step[k] = xd[k] > 0 ? 1 : xd[k] < 0 ? -1 : 0;
            delta[k] = xd[k] != 0 ? std::abs(size / xd[k]) : INFINITY;
            next[k] = xd[k] != 0 ? t + ((xd[k] > 0 ? c + 1 : c) * size - x[k]) / xd[k] : INFINITY;
        }
    }
    int exitAxis() const { return next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2); }
    void advance(int axis) {
        at[axis] += step[axis];
        next[axis] += delta[axis];
    }
    /// Keeps the cube within [lo, hi] per axis (a start on a face may round
    /// to the cube outside), moving its exits with it.
    void clamp(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi) {
        for (int k = 0; k < 3; ++k) {
            const int moved = std::clamp(at[k], lo[k], hi[k]) - at[k];
            at[k] += moved;
            if (step[k] != 0) next[k] += moved * step[k] * delta[k];
        }
    }
};

class VdbCellTracer final : public ShapeCellTracer<VdbLevelSetField> {
public:
    explicit VdbCellTracer(const ShapeCell<VdbLevelSetField>& cell) : ShapeCellTracer(cell) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        Vec3 o, d;
        if (!leafSegment(origin, direction, o, d, t0, t1)) return r;
        const VdbLevelSet& levelSet = *shape_.levelSet;
        const LevelSetGridData& grid = levelSet.grid();
        const Vec3 xo = levelSet.indexOf(o), xd = levelSet.indexDirectionOf(d);
        // Beyond the blocks every voxel is the background: no surface.
        constexpr int n = kVoxelBlockCells;
        const Eigen::Vector3i origin8(grid.blockOrigin[0], grid.blockOrigin[1], grid.blockOrigin[2]);
        const Eigen::Vector3i count(grid.blockCount[0], grid.blockCount[1], grid.blockCount[2]);
        const Box3 blocks(Vec3(n * origin8.cast<double>()), Vec3(n * (origin8 + count).cast<double>()));
        if (!clipRayToBox(blocks, xo, xd, t0, t1) || !(t0 < t1)) return r;
        const Settings walk{settings.epsilon / direction.norm(), xd.norm(), settings.anyHit};

        // Blocks first: those no surface crosses are passed in one step.
        GridWalk block(xo, xd, t0, n);
        block.clamp(origin8, origin8 + count - Eigen::Vector3i::Ones());
        const Eigen::Vector3i relative = block.at - origin8;
        size_t index = size_t(relative.x()) + size_t(count.x()) * (size_t(relative.y()) + size_t(count.y()) * relative.z());
        const long long indexStep[3] = {block.step[0], block.step[1] * (long long)count.x(),
                                        block.step[2] * (long long)count.x() * count.y()};
        double t = t0;
        while (t < t1) {
            const int axis = block.exitAxis();
            const double blockEnd = std::min(block.next[axis], t1);
            ++r.steps;
            if (const uint32_t f = grid.footprintOf[index]; f != kNoFootprint) {
                const float* footprint = grid.footprints.data() + size_t(f) * kFootprintVoxels;
                if (walkBlock(r, footprint, grid.blocks[index].gradient, block.at * n, xo, xd, t, blockEnd, walk)) {
                    recordShapeHit(r, r.t, o, d);
                    return r;
                }
            }
            t = block.next[axis];
            block.advance(axis);
            const int at = block.at[axis] - origin8[axis];
            if (at < 0 || at >= count[axis]) break;
            index += indexStep[axis];
        }
        return r;
    }

private:
    struct Settings {
        double tolerance;  ///< in t
        double speed;      ///< voxels per unit of t
        bool anyHit;
    };

    // The cells of one block, [t, end] of the ray: skips cells whose corners
    // share a sign (by sphere steps under the block's gradient bound where
    // those pass more than a cell) and solves the others' trilinear cubic.
    // True, with r.t, at the first root.
    static bool walkBlock(CellTraceResult& r, const float* footprint, float gradient, const Eigen::Vector3i& first,
                          const Vec3& xo, const Vec3& xd, double t, double end, const Settings& s) {
        const Eigen::Vector3i last = first + Eigen::Vector3i::Constant(kVoxelBlockCells - 1);
        GridWalk cell(xo, xd, t, 1.0);
        cell.clamp(first, last);
        float v[8];
        while (t < end) {
            const int axis = cell.exitAxis();
            const double cellEnd = std::min(cell.next[axis], end);
            ++r.steps;
            ++r.evaluations;
            const Eigen::Vector3i local = cell.at - first;
            VdbLevelSet::footprintCorners(footprint, (local.z() * kFootprintSide + local.y()) * kFootprintSide + local.x(), v);
            const float lo = std::min({v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
            const float hi = std::max({v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
            if (lo <= 0 && hi >= 0) {
                // About the cell's entry, where the local coordinates lie in [0, 1].
                const Vec3 a = xo + t * xd - cell.at.cast<double>();
                if (const auto root = firstBernsteinRoot<3>(trilinearAlongLine(v, a, xd), 0.0, cellEnd - t, s.tolerance,
                                                            nullptr, s.anyHit)) {
                    r.hit = true;
                    r.t = t + *root;
                    return true;
                }
            } else if (gradient > 0) {
                // |f| >= margin over the cell, and changes by at most
                // `gradient` per voxel within the block: no zero closer.
                const double safe = t + double(lo > 0 ? lo : -hi) / (double(gradient) * s.speed);
                if (safe > cell.next[axis] + cell.delta[axis]) {
                    if (safe >= end) return false;
                    t = safe;
                    cell = GridWalk(xo, xd, t, 1.0);
                    cell.clamp(first, last);
                    continue;
                }
            }
            t = cell.next[axis];
            cell.advance(axis);
            const int at = cell.at[axis];
            if (at < first[axis] || at > last[axis]) return false;
        }
        return false;
    }
};

}  // namespace

bool VdbCellAccelerator::marchesWholeField(const FieldProgram& field, const Box3&) const {
    return bareShape<VdbLevelSetField>(field) != nullptr;
}

std::optional<CellAcceleration> VdbCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                               double) const {
    const ShapeCell<VdbLevelSetField> cell(program, box);
    if (!cell.shape) return std::nullopt;
    CellAcceleration a;
    if (cell.part.isEmpty()) return a;
    a.parts = worldPartBoxes(*cell.placement, {cell.part}, box);
    a.tracer = std::make_unique<VdbCellTracer>(cell);
    return a;
}

}  // namespace isotrace::geometry
