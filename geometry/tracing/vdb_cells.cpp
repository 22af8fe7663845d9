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

class VdbCellTracer final : public ShapeCellTracer<VdbLevelSetField> {
public:
    explicit VdbCellTracer(const ShapeCell<VdbLevelSetField>& cell) : ShapeCellTracer(cell) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        Vec3 o, d;
        if (!leafSegment(origin, direction, o, d, t0, t1)) return r;
        const VdbLevelSet& levelSet = *shape_.levelSet;
        const Vec3 xo = levelSet.indexOf(o), xd = levelSet.indexDirectionOf(d);
        const double tolerance = settings.epsilon / direction.norm();
        const double speed = xd.norm();  // voxels per unit of t
        Eigen::Vector3i cell, step;
        Vec3 tNext, tDelta;
        for (int k = 0; k < 3; ++k) {
            step[k] = xd[k] > 0 ? 1 : xd[k] < 0 ? -1 : 0;
            tDelta[k] = xd[k] != 0 ? std::abs(1.0 / xd[k]) : INFINITY;
        }
        // The cell holding the ray at t (stepping the way the ray goes where
        // it lies on a face), and when the ray leaves it along each axis.
        auto locate = [&](double t) {
            const Vec3 x = xo + t * xd;
            for (int k = 0; k < 3; ++k) {
                double c = std::floor(x[k]);
                if (xd[k] < 0 && c == x[k]) c -= 1;
                cell[k] = int(c);
                tNext[k] = xd[k] != 0 ? t + ((xd[k] > 0 ? c + 1 : c) - x[k]) / xd[k] : INFINITY;
            }
        };
        // When the ray leaves the current cell's block.
        auto blockExit = [&](double t) {
            const Vec3 x = xo + t * xd;
            double exit = INFINITY;
            for (int k = 0; k < 3; ++k) {
                if (xd[k] == 0) continue;
                const int block = (cell[k] >= 0 ? cell[k] : cell[k] - (kVoxelBlockCells - 1)) / kVoxelBlockCells;
                const double face = kVoxelBlockCells * double(xd[k] > 0 ? block + 1 : block);
                exit = std::min(exit, t + (face - x[k]) / xd[k]);
            }
            return exit;
        };
        double t = t0;
        locate(t);
        float v[8];
        while (t < t1) {
            const int axis = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
            const double cellExit = tNext[axis];
            ++r.steps;
            int offset;
            float gradient;
            const float* footprint = levelSet.footprintOf(cell, offset, gradient);
            double jump = -INFINITY;  // where the next cell to look at is, when more than one cell on
            if (!footprint) {
                // No zero in the block: on to the next.
                jump = std::max(blockExit(t), cellExit);
            } else {
                VdbLevelSet::footprintCorners(footprint, offset, v);
                ++r.evaluations;
                const float lo = std::min({v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
                const float hi = std::max({v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
                if (lo <= 0 && hi >= 0) {
                    // About the cell's entry, where the local coordinates lie in [0, 1].
                    const Vec3 a = xo + t * xd - cell.cast<double>();
                    const auto s = firstBernsteinRoot<3>(trilinearAlongLine(v, a, xd), 0.0, std::min(cellExit, t1) - t,
                                                         tolerance, nullptr, settings.anyHit);
                    if (s) {
                        recordShapeHit(r, t + *s, o, d);
                        return r;
                    }
                } else if (gradient > 0) {
                    // |f| >= margin over the cell, and changes by at most
                    // `gradient` per voxel within the block: no zero closer.
                    const double margin = lo > 0 ? lo : -hi;
                    const double safe = t + margin / (double(gradient) * speed);
                    if (safe > cellExit + tDelta[axis]) jump = std::min(safe, blockExit(t));
                }
            }
            if (jump > cellExit) {
                t = jump;
                if (t >= t1) break;
                locate(t);
                continue;
            }
            t = cellExit;
            cell[axis] += step[axis];
            tNext[axis] += tDelta[axis];
        }
        return r;
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
