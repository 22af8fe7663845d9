// Cells where a variational field meets other operands of a CSG tree (or a
// blend) march through a local model of the variational leaf instead of
// summing its N terms at every step. The model (variational_patch.h) holds
// the leaf's value within a proven error over the cell; every operator is
// monotone in each operand, so the tree evaluated at the two ends of that
// interval bounds its value: where the bound excludes zero it certifies the
// sign and a step of |bound| / L, and only where it cannot (within about the
// model's error of the surface) is the exact tree evaluated. L comes from
// the models' gradient bounds, far tighter than interval sums over the cell.
// Hermite fields are modelled alike (their gradient terms in the model).
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class VariationalCsgCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
