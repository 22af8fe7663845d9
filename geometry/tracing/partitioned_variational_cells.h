// Cells of a partitioned variational fit (pointsets/variational_partition.h:
// r^3 interpolants blended by MPU's weights) marched on local models instead
// of exact sums. An exact evaluation sums every centre of every interpolant
// whose ball reaches the point, a few thousand kernels; each part of a cell
// keeps instead one model per interpolant (variational/variational_patch.h:
// a Taylor polynomial with proven value and gradient errors), so a step costs
// a few polynomials. Signs and steps stay proven: see the source.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class PartitionedVariationalCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
