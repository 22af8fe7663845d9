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
    /// surface's diagonal.
    explicit VariationalCellAccelerator(double relativeTolerance = 1e-4) : relativeTolerance_(relativeTolerance) {}

    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;

private:
    double relativeTolerance_;
};

}  // namespace isotrace::geometry
