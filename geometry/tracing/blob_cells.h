// Cells whose program is one blobby leaf with a polynomial kernel (the
// (1 - a^2)^3 falloff, Wyvill's soft objects) are not marched: each kernel
// is a cubic in a^2 = |x - c|^2 / R^2, a quadratic along a ray, so inside
// its ball every blob is a polynomial of degree 6 in t and the field
// T - sum w_i k_i is one between the points where the ray enters or leaves
// a ball. Its first root is isolated exactly (segment_polynomial.h): each
// blob the ray passes through is turned into a polynomial once, instead of
// being evaluated at every step. A shaped blob (a segment, rectangle or box
// core in its own frame) is such a polynomial on each of the up to seven
// pieces between the points where the ray crosses its core's face planes.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class BlobCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
