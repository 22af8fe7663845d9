// Cells whose program is one MPU leaf are not marched: each is split into
// small parts that may hold surface (interval ranges of N), each part keeps
// the locals whose balls reach it, and a ray through a part finds its first
// root exactly on the piecewise polynomial N takes along it
// (pointsets/mpu_ray_segment.h). Parts are Embree primitives of their own,
// so the BVH skips the space they leave out.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class MpuCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
