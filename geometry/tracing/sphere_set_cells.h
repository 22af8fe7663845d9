// Cells whose program is a union of spheres (a sphere set pruned to the
// cell, alone or as a difference's carving operand) are not marched: along
// a ray the union's boundary is where the ray first enters a sphere from
// outside them all, or, from inside, where the chain of overlapping spans
// it is in ends. Each sphere's span is a quadratic's roots, so a cell of a
// few dozen spheres costs a few dozen of them, exactly. One tracer serves
// every such cell of a surface (CellTracer::absorb), each cell a run of its
// list of members.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

/// What a ray pays per cell over sphere sets: in a lone union of spheres
/// (up to sign) one quadratic per sphere reaching the cell, elsewhere an
/// evaluation of every member per step. The octree refines cells over
/// sets until this is small.
size_t sphereSetCellCost(const FieldProgram& cellProgram, const Box3& cellBox);

class SphereSetCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
};

}  // namespace isotrace::geometry
