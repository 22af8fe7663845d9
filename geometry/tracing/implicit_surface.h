// An implicit surface ready for ray tracing: the field's bounds split by an
// adaptive octree into cells that may hold surface (cells whose value range
// excludes zero are dropped), each cell with its own Lipschitz bound and its
// own pruned copy of the field. Embree's BVH over the cells skips empty
// space; each march uses the tightest bound and the shortest program there.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/field_program.h"
#include "geometry/tracing/sphere_tracer.h"
#include "geometry/variational/variational_patch.h"

namespace isotrace::geometry {

struct ImplicitSurfaceOptions {
    int maxDepth = 6;            ///< octree levels below the bounds
    size_t cellBudget = 16384;   ///< stop refining before a level would exceed this
    double relativeEpsilon = 1e-6;  ///< hit precision, relative to the bounds' diagonal
    bool pruneCells = true;      ///< per-cell pruning (off only to measure it)
    /// One global bound for every cell instead of local ones (benchmarks only).
    bool globalLipschitzOnly = false;
    /// Cells whose program is a bare variational field march through local
    /// models (variational_patch.h) instead of O(N) sums (off only to
    /// measure it).
    bool variationalPatches = true;
    /// Their models' value error target, relative to the bounds' diagonal.
    double patchRelativeTolerance = 1e-4;
};

struct SurfaceCell {
    Box3 box;
    double lipschitz = 0.0;
    uint32_t program = 0;  ///< index into ImplicitSurface::cellPrograms
    int32_t variational = -1;  ///< index of its local models, or -1
};

/// A cell whose program is one variational leaf: one of the models built
/// for the octree cell it came from (in the leaf's frame; the cell's box
/// bounds the model's box in the world), and how to reach that frame. Each
/// model that may hold surface is a cell of its own, so Embree's BVH skips
/// the space the models prove empty.
struct VariationalCell {
    VariationalPatch model;
    const VariationalField* field = nullptr;  ///< owned by the cell's program
    LeafPlacement placement;
};

/// Per-thread totals of the marching work, read by benchmarks and AOVs.
struct TraceCounters {
    uint64_t steps = 0;
    uint64_t evaluations = 0;
};
TraceCounters& threadTraceCounters();

class ImplicitSurface {
public:
    /// Fails (std::invalid_argument) when the field's bounds are not finite.
    explicit ImplicitSurface(FieldProgram field, const ImplicitSurfaceOptions& options = {});

    const FieldProgram& field() const { return field_; }
    const Box3& bounds() const { return bounds_; }
    const std::vector<SurfaceCell>& cells() const { return cells_; }
    const FieldProgram& cellProgram(const SurfaceCell& c) const { return programs_[c.program]; }
    const TraceSettings& traceSettings() const { return settings_; }
    double globalLipschitz() const { return globalLipschitz_; }
    size_t variationalCellCount() const { return variationalCells_.size(); }

    /// Nearest hit in one cell for t in (tNear, tFar); counts its work.
    TraceResult intersectCell(uint32_t cell, const Vec3& origin, const Vec3& direction, double tNear,
                              double tFar) const;
    /// Nearest hit over all cells without Embree (tests, tools): a linear scan.
    TraceResult intersect(const Vec3& origin, const Vec3& direction, double tNear, double tFar) const;
    /// Unit outward normal (normalised field gradient) at a point near the surface.
    Vec3 normal(const Vec3& p) const;

    /// Ray mask bits this surface answers to (set when attached to Embree).
    unsigned rayMask() const { return rayMask_; }
    void setRayMask(unsigned mask) { rayMask_ = mask; }

private:
    /// A variational cell's march through its model (in the leaf's frame),
    /// falling back to the general tracer if the model's march runs out of
    /// steps.
    TraceResult traceModel(const SurfaceCell& cell, const Vec3& origin, const Vec3& direction, double t0,
                           double t1) const;

    unsigned rayMask_ = 0xFFFFFFFFu;
    FieldProgram field_;
    Box3 bounds_;
    std::vector<SurfaceCell> cells_;
    std::vector<FieldProgram> programs_;
    std::vector<VariationalCell> variationalCells_;
    TraceSettings settings_;
    double globalLipschitz_ = 0.0;
};

}  // namespace isotrace::geometry
