// Cells whose program is one box (rounded or not), or its complement, are
// not marched. A rounded box is the union of three boxes (the core grown by
// the rounding along one axis each), twelve cylinders along the core's
// edges and eight balls at its corners; a ray enters the solid where it
// first enters one of them and leaves where it last leaves one, each found
// in closed form. A cell keeps only the pieces that reach it (most cells
// lie on a flat face: one slab test).
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class BoxCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
    /// A bare sharp box is (one slab test in any box); a rounded one is
    /// not: its cells keep one piece each, the whole box 23.
    bool marchesWholeField(const FieldProgram& field, const Box3& box) const override;
};

}  // namespace isotrace::geometry
