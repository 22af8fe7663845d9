// Cells whose program is one OpenVDB level set (alone, or what is left of a
// CSG tree where only it can hold surface) are not sphere traced: the ray
// walks the voxel cells it crosses (a 3D DDA), skips those whose eight
// corners share a sign, and in the others solves the trilinear interpolant
// along the ray, a cubic in t, for its first root exactly. Sphere tracing a
// level set takes many steps where rays graze it, each a voxel lookup.
#pragma once

#include "geometry/tracing/cell_accelerator.h"

namespace isotrace::geometry {

class VdbCellAccelerator final : public CellAccelerator {
public:
    std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                               double surfaceDiagonal) const override;
    /// A bare one is: the walk skips the blocks no surface crosses by
    /// itself, and an octree of parts would only add Embree calls.
    bool marchesWholeField(const FieldProgram& field, const Box3& box) const override;
};

}  // namespace isotrace::geometry
