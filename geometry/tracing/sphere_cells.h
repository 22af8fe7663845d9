// Cells whose program is one sphere (alone, or what is left of a CSG tree
// where only a sphere can hold surface) are not marched: the first root of
// |o + t d - c| = r is the smaller root of a quadratic in t, in closed form,
// where sphere tracing converges on it step by step (many steps for rays
// that graze it).
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class SphereCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
    /// A bare one is: its root along a ray costs the same in any box.
    bool marchesWholeField(const FieldProgram& field, const Box3& box) const override;
};

}  // namespace isotrace::geometry
