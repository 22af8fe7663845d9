// Cells where a few spheres, boxes and ring tori meet in a sharp CSG tree
// (union, intersection, difference: min, max and negation) are not
// marched. Along a ray each shape is inside on at most two spans, found in
// closed form or by exact quartic roots (shape_spans.h); the tree's solid
// is the same set operations on those spans, and the first surface point in
// the cell is the first span end that a shape, not the cell's wall, set.
// This is how POV-Ray and the classic CSG ray tracers (Roth 1982) meet CSG;
// sphere tracing slows down at such edges, where the tree's value is only a
// bound on the distance.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class CsgCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
