// Cells whose program is one algebraic surface (a polynomial leaf: the
// quadrics, Goursat's tangle and its kin) are not marched: along a ray
// x = o + t d the polynomial is itself a polynomial in t of the same degree,
// so its first root in the cell is isolated exactly in the Bernstein basis
// (bernstein_root.h), as POV-Ray solves its quartics, instead of stepping by
// a Lipschitz bound that is loose where the gradient nearly vanishes.
#pragma once

#include <mutex>
#include <unordered_map>

#include "geometry/fields/polynomial.h"
#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class PolynomialCellAccelerator final : public CellAccelerator {
public:
    /// Degrees above this are left to the sphere tracer (the Bernstein
    /// hull's work grows with the square of the degree). 16 takes every
    /// preset: the decocube is of degree 12, pretzel4 of 16.
    static constexpr int kMaxDegree = 16;

    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
    /// A bare polynomial is: a ray's root search over its whole segment costs
    /// less than the Embree calls of the octree's cells it crosses
    /// (bench/RESULTS.md, "Tuned constants").
    bool marchesWholeField(const FieldProgram& field, const Box3& box) const override;

private:
    template <int Degree>
    std::unique_ptr<CellTracer> tracerFor(const PolynomialField& field, const LeafPlacement& placement, uint64_t key,
                                          bool negated, const Box3& part) const;

    // The surfaces the cells share, by content key (cells are offered in
    // parallel, at load time only).
    mutable std::mutex mutex_;
    mutable std::unordered_map<uint64_t, std::shared_ptr<const void>> surfaces_;
};

}  // namespace isotrace::geometry
