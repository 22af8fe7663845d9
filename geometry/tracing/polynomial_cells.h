// Cells whose program is one algebraic surface (a polynomial leaf: the
// quadrics, Goursat's tangle and its kin) are not marched: along a ray
// x = o + t d the polynomial is itself a polynomial in t of the same degree,
// so its first root in the cell is isolated exactly in the Bernstein basis
// (bernstein_root.h), as POV-Ray solves its quartics, instead of stepping by
// a Lipschitz bound that is loose where the gradient nearly vanishes.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class PolynomialCellAccelerator final : public CellAccelerator {
public:
    /// Degrees above this are left to the sphere tracer (the Bernstein
    /// hull's work grows with the square of the degree).
    static constexpr int kMaxDegree = 8;

    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
