// Cells whose program is one variational leaf march through local models
// (variational/variational_patch.h) instead of O(N) sums: each model that
// may hold surface is a part of its own, so Embree's BVH skips the space
// the models prove empty, and a part is marched in the leaf's frame (an
// affine map keeps the ray's t) by tracePatch.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class VariationalCellAccelerator final : public CellAccelerator {
public:
    /// `relativeTolerance`: the models' value error target, relative to the
    /// surface's diagonal; boxes are split at most `maxDepth` times below a
    /// cell. The defaults make most models exact to the default hit
    /// precision (1e-6 of the diagonal) within half their half-diagonal of
    /// their centre, where the tracer takes hits from the model alone
    /// (patch_tracer.h). Tighter models cost loading time; looser ones send
    /// more hits to exact sums. bench/variational_render decides the
    /// defaults (bench/RESULTS.md, "Tuned constants").
    explicit VariationalCellAccelerator(double relativeTolerance = 1.5e-5, int maxDepth = 4)
        : relativeTolerance_(relativeTolerance), maxDepth_(maxDepth) {}

    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;

private:
    double relativeTolerance_;
    int maxDepth_;
};

}  // namespace isotrace::geometry
