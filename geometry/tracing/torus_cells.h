// Cells whose program is one ring torus (or its complement, as a carving
// torus leaves in the cells of a difference) are not marched: along a ray
// its surface is the quartic (|d|^2 + R^2 - r^2)^2 = 4 R^2 (d_x^2 + d_z^2),
// d = x - centre, whose first root in the cell is isolated exactly in the
// Bernstein basis (bernstein_root.h). Spindle tori (r >= R) are left to the
// sphere tracer: their quartic has a second, inner sheet the distance
// field does not.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class TorusCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
    /// A bare one is: its root along a ray costs the same in any box.
    bool marchesWholeField(const FieldProgram& field, const Box3& box) const override;
};

}  // namespace isotrace::geometry
