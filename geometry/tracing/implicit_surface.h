// An implicit surface ready for ray tracing: the field's bounds split by an
// adaptive octree into cells that may hold surface (cells whose value range
// excludes zero are dropped), each cell with its own Lipschitz bound and its
// own pruned copy of the field. Embree's BVH over the cells skips empty
// space; each march uses the tightest bound and the shortest program there.
// A field an accelerator solves exactly in any box (a bare sphere, ring
// torus, sharp box or polynomial: CellAccelerator::marchesWholeField) is one
// cell, the box the octree proves it lies in.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/field_program.h"
#include "geometry/tracing/cell_accelerator.h"
#include "geometry/tracing/sphere_tracer.h"

namespace isotrace::geometry {

/// The accelerators every surface uses unless told otherwise.
std::vector<std::shared_ptr<const CellAccelerator>> defaultCellAccelerators();

struct ImplicitSurfaceOptions {
    int maxDepth = 6;            ///< octree levels below the bounds
    /// Cells where the field is a distance bound (one primitive; two
    /// combined one level deeper) stop splitting at this depth: sphere
    /// tracing steps by their value already, and analytic tracers need no
    /// small cells, so deeper ones only cost start-up (bench/RESULTS.md,
    /// "Tuned constants"). Code that scans cells for surface wants them
    /// deeper.
    int distanceCellDepth = 1;
    size_t cellBudget = 16384;   ///< stop refining before a level would exceed this
    double relativeEpsilon = 1e-6;  ///< hit precision, relative to the bounds' diagonal
    bool pruneCells = true;      ///< per-cell pruning (off only to measure it)
    /// One global bound for every cell instead of local ones (benchmarks only).
    bool globalLipschitzOnly = false;
    /// Offered every cell in turn; the first that takes it marches it. By
    /// default variational fields march through local models
    /// (variational_cells.h); clear it only to measure what they save.
    std::vector<std::shared_ptr<const CellAccelerator>> cellAccelerators = defaultCellAccelerators();
};

/// One Embree primitive. What every ray offered the cell reads (box, band,
/// tracer) fills its first two cache lines; the part's payload the next
/// two, read only by rays that reach the band.
struct alignas(64) SurfaceCell {
    Box3 box;
    /// An accelerated part's band (CellAcceleration::bands), next to its
    /// box: what a ray offered the part reads first.
    PartBand band;
    uint32_t program = 0;  ///< index into ImplicitSurface::cellPrograms
    int32_t tracer = -1;   ///< the accelerator's tracer that marches it, or -1
    uint32_t part = 0;     ///< which of that tracer's parts it is
    double lipschitz = 0.0;
    PartPayload payload;  ///< an accelerated part's (CellAcceleration::payloads)
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
    /// The box the cells were refined from: the field's bounds, or the
    /// smaller box interval ranges prove holds all of the surface.
    const Box3& refinementRoot() const { return refinementRoot_; }
    const std::vector<SurfaceCell>& cells() const { return cells_; }
    const FieldProgram& cellProgram(const SurfaceCell& c) const { return programs_[c.program]; }
    const TraceSettings& traceSettings() const { return settings_; }
    double globalLipschitz() const { return globalLipschitz_; }
    /// Cells marched by an accelerator rather than the general tracer.
    size_t acceleratedCellCount() const;
    /// The accelerators' tracers those cells share (CellTracer::absorb).
    size_t tracerCount() const { return tracers_.size(); }

    /// Nearest hit in one cell for t in (tNear, tFar); counts its work.
    /// With anyHit (occlusion), any hit in the segment (TraceSettings::anyHit).
    TraceResult intersectCell(uint32_t cell, const Vec3& origin, const Vec3& direction, double tNear, double tFar,
                              bool anyHit = false) const;
    /// Nearest hit over all cells without Embree (tests, tools): a linear scan.
    TraceResult intersect(const Vec3& origin, const Vec3& direction, double tNear, double tFar) const;
    /// Unit outward normal (normalised field gradient) at a point near the surface.
    Vec3 normal(const Vec3& p) const;

    /// Ray mask bits this surface answers to (set when attached to Embree).
    unsigned rayMask() const { return rayMask_; }
    void setRayMask(unsigned mask) { rayMask_ = mask; }

private:
    unsigned rayMask_ = 0xFFFFFFFFu;
    FieldProgram field_;
    Box3 bounds_;
    Box3 refinementRoot_;
    std::vector<SurfaceCell> cells_;
    std::vector<FieldProgram> programs_;
    std::vector<std::unique_ptr<CellTracer>> tracers_;
    TraceSettings settings_;
    double globalLipschitz_ = 0.0;
};

}  // namespace isotrace::geometry
