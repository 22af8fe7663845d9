// A hook for marching some cells of an implicit surface faster than the
// general sphere tracer can. ImplicitSurface offers every octree cell (with
// its pruned program) to its accelerators; one that recognises the program
// takes the cell over, splits it into parts (world boxes, each an Embree
// primitive of its own; none when it proves the cell empty) and marches
// each part itself. Variational fields use it (variational_cells.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/field_program.h"
#include "geometry/tracing/sphere_tracer.h"

namespace isotrace::geometry {

struct CellTraceResult : TraceResult {
    /// False when the march gave up at t (a ray grazing the surface for a
    /// long way): the general tracer settles [t, restEnd].
    bool complete = true;
    double restEnd = 0.0;
};

/// A slab that holds a part's surface, in the leaf's frame: within the
/// part, f stays within halfWidth of the plane value + slope . (x - point),
/// so a ray that stays out of the slab meets no surface there. Most rays
/// Embree offers a part pass it by; ImplicitSurface keeps each part's band
/// beside its box, so those rays cost the tracer none of the part's own
/// (larger, elsewhere in memory) data: on a 37,822-vertex MPU model that
/// second cache miss per part offered was a tenth of the frame.
struct PartBand {
    Vec3 point = Vec3::Zero(), slope = Vec3::Zero();
    double value = 0.0;
    double halfWidth = std::numeric_limits<double>::infinity();  ///< infinite: no band known

    double at(const Vec3& x) const { return value + slope.dot(x - point); }
    /// The ray's t where it enters and leaves the slab (raySlabSpan); false
    /// when it never does.
    bool span(const Vec3& origin, const Vec3& direction, double& enter, double& leave) const {
        return raySlabSpan(at(origin), slope.dot(direction), halfWidth, enter, leave);
    }
};

/// The box around what of `box` lies inside the band's slab: the part's
/// surface lies there, so Embree, offered this box instead, calls the tracer
/// for fewer rays (a ray leaving the surface crosses the boxes of the parts
/// beside its origin, and most of those only outside their slabs). Per
/// axis, x_k's range where the slab's value (the other axes spanning the
/// box) can reach [-halfWidth, halfWidth]; widened for rounding, never
/// beyond `box`; empty when the slab misses the box.
inline Box3 boxAroundBand(const Box3& box, const PartBand& band) {
    if (box.isEmpty() || !std::isfinite(band.halfWidth)) return box;
    Box3 around = box;
    const double slack = 1e-9 * box.extent().norm();
    for (int k = 0; k < 3; ++k) {
        const double s = band.slope[k];
        if (s == 0.0) continue;
        double lo = band.value, hi = band.value;  // the others' share of the plane's value
        for (int j = 0; j < 3; ++j) {
            if (j == k) continue;
            const double a = band.slope[j] * (box.lower[j] - band.point[j]);
            const double b = band.slope[j] * (box.upper[j] - band.point[j]);
            lo += std::min(a, b);
            hi += std::max(a, b);
        }
        // lo + s (x - p) <= halfWidth and hi + s (x - p) >= -halfWidth.
        double first = band.point[k] + (-band.halfWidth - hi) / s, second = band.point[k] + (band.halfWidth - lo) / s;
        if (first > second) std::swap(first, second);
        around.lower[k] = std::max(box.lower[k], first - slack);
        around.upper[k] = std::min(box.upper[k], second + slack);
    }
    return around;
}

/// A part's quadratic model of the sum it traces, beyond what its band
/// holds (the value and gradient at the centre): the Hessian's upper
/// triangle and proven errors over the part (pointsets/mpu_numerator_model.h
/// defines them).
struct PartQuadraticModel {
    double hessian[6] = {};  ///< xx xy xz yy yz zz
    double valueError = 0.0, slopeError = 0.0, hessianError = 0.0;
    double remainderThird = 0.0, valueFloor = 0.0, slopeFloor = 0.0;

    Vec3 times(const Vec3& v) const {
        return {hessian[0] * v.x() + hessian[1] * v.y() + hessian[2] * v.z(),
                hessian[1] * v.x() + hessian[3] * v.y() + hessian[4] * v.z(),
                hessian[2] * v.x() + hessian[4] * v.y() + hessian[5] * v.z()};
    }
};

/// What an accelerator keeps of each part inline, after its box and band
/// in the same cell record (ImplicitSurface's SurfaceCell), so that a ray
/// that reaches the band finds it without a second lookup: the part's run
/// of its tracer's list of terms, and its model.
struct PartPayload {
    uint32_t firstTerm = 0, termCount = 0;
    uint32_t singleTerms = 0;  ///< terms of one piece, which come first in the run
    uint32_t pieceCodes = 0;   ///< which piece the terms after them take, where the part proves it
    PartQuadraticModel model;
};

struct CellAcceleration;

/// Marches the parts of the cells one accelerator took over.
class CellTracer {
public:
    virtual ~CellTracer() = default;
    /// First root along origin + t direction for t in [t0, t1], a segment
    /// already clipped to the part's box; `band` and `payload` are the
    /// part's (CellAcceleration::bands and payloads; an infinite band and
    /// zeros when the accelerator gave none).
    virtual CellTraceResult trace(uint32_t part, const PartBand& band, const PartPayload& payload, const Vec3& origin,
                                  const Vec3& direction, double t0, double t1, const TraceSettings& settings) const = 0;
    /// Whether trace() stays exact on a segment that starts a resolution
    /// step before the part's box: ImplicitSurface starts segments there, so
    /// that a surface on the face a ray enters by (a CSG cut on one of the
    /// octree's planes) is seen crossing. Tracers whose models are proven
    /// only within their parts say no.
    virtual bool tracesFromBeforeItsPart() const { return true; }
    /// Takes over the parts of another cell's acceleration by the same
    /// accelerator, so that one tracer marches many cells and stays in
    /// cache. Returns where `other`'s parts and terms go in this tracer:
    /// its first part's index (its others follow in order) and the offset
    /// its payloads' runs of terms move by, which the caller applies.
    /// nullopt, the default, when it cannot, and `other` keeps its tracer.
    /// Called while the surface is built, one cell after another.
    struct Absorbed {
        uint32_t firstPart = 0;
        uint32_t termOffset = 0;
    };
    virtual std::optional<Absorbed> absorb(const CellAcceleration& other) { return std::nullopt; }
};

struct CellAcceleration {
    std::unique_ptr<CellTracer> tracer;
    std::vector<Box3> parts;  ///< world boxes within the cell, indexed as trace()'s `part`
    std::vector<PartBand> bands;  ///< one per part, or none
    std::vector<PartPayload> payloads;  ///< one per part, or none
};

// Accelerators work in their leaf's frame (an affine map keeps a ray's t):
// these carry rays, gradients and part boxes between it and the world.

/// The ray's origin and direction in the leaf's frame.
inline void rayInLeafFrame(const LeafPlacement& placement, const Vec3& origin, const Vec3& direction, Vec3& leafOrigin,
                           Vec3& leafDirection) {
    leafOrigin = placement.leafFromWorld(origin);
    leafDirection = placement.identity ? direction : Vec3(placement.linear * direction);
}

/// The world gradient of valueScale f(A x + b): valueScale A^T grad f.
inline Vec3 worldGradient(const LeafPlacement& placement, const Vec3& leafGradient) {
    return placement.valueScale * (placement.identity ? leafGradient : Vec3(placement.linear.transpose() * leafGradient));
}

/// The world boxes, within the octree cell `cell`, around parts given in
/// the leaf's frame.
inline std::vector<Box3> worldPartBoxes(const LeafPlacement& placement, const std::vector<Box3>& leafParts,
                                        const Box3& cell) {
    if (placement.identity) return leafParts;
    const Mat3 worldFromLeaf = placement.linear.inverse();
    std::vector<Box3> boxes;
    boxes.reserve(leafParts.size());
    for (const Box3& part : leafParts) {
        const Box3 around = transformBox(worldFromLeaf, -(worldFromLeaf * placement.offset), part);
        boxes.emplace_back(around.lower.cwiseMax(cell.lower), around.upper.cwiseMin(cell.upper));
    }
    return boxes;
}

/// The part of `box` that can hold surface, to the resolution of two
/// further bisections: the union of the sub-cells of sub-cells whose range
/// (`range(box)`, an Interval) holds zero; empty when none does. A sub-cell
/// already inside the union cannot widen it and is not tested (up to 72
/// range tests per cell were a third of the time cells took to build).
template <typename RangeOf>
Box3 shrunkToSurface(const Box3& box, const RangeOf& range) {
    Box3 kept;
    auto within = [&kept](const Box3& b) { return kept.contains(b.lower) && kept.contains(b.upper); };
    for (int i = 0; i < 8; ++i) {
        const Box3 child = box.octant(i);
        if (within(child) || !range(child).containsZero()) continue;
        for (int k = 0; k < 8; ++k) {
            const Box3 grandchild = child.octant(k);
            if (!within(grandchild) && range(grandchild).containsZero()) kept.extend(grandchild);
        }
    }
    return kept;
}

/// Records a hit at t on a leaf shape, with its gradient there (in the
/// leaf's frame, then the world's; `sign` -1 for a complement).
template <typename Shape>
void recordHit(CellTraceResult& r, double t, const Shape& shape, const Vec3& leafOrigin, const Vec3& leafDirection,
               const LeafPlacement& placement, double sign) {
    r.hit = true;
    r.t = t;
    Vec3 gradient;
    shape.valueAndGradient(leafOrigin + t * leafDirection, gradient);
    r.gradientKnown = true;
    r.gradient = worldGradient(placement, sign * gradient);
}

/// The program's one leaf if it is of kind `Shape` (alone or its
/// complement), or null.
template <typename Shape>
const Shape* bareShape(const FieldProgram& program) {
    bool negated = false;
    const FieldLeaf* leaf = program.leafUpToSign(negated);
    return leaf ? std::get_if<Shape>(&leaf->shape) : nullptr;
}

/// A cell whose program is one leaf of kind `Shape` or its complement (as
/// a difference leaves its carving operand): the shape, and the cell shrunk
/// to its surface in the leaf's frame. `shape` is null for other programs.
template <typename Shape>
struct ShapeCell {
    const Shape* shape = nullptr;
    const LeafPlacement* placement = nullptr;
    bool negated = false;
    Box3 part;  ///< empty when the cell holds no surface

    ShapeCell(const FieldProgram& program, const Box3& cellBox) {
        const FieldLeaf* leaf = program.leafUpToSign(negated);
        shape = leaf ? std::get_if<Shape>(&leaf->shape) : nullptr;
        if (!shape) return;
        placement = &leaf->placement;
        const Box3 leafBox =
            placement->identity ? cellBox : transformBox(placement->linear, placement->offset, cellBox);
        part = shrunkToSurface(leafBox, [this](const Box3& b) { return shape->range(b); });
    }
    double sign() const { return negated ? -1.0 : 1.0; }
};

/// The tracer of a ShapeCell: the shape, its placement, the sign and the
/// part, and the ray's segment in the leaf's frame.
template <typename Shape>
class ShapeCellTracer : public CellTracer {
protected:
    explicit ShapeCellTracer(const ShapeCell<Shape>& cell)
        : shape_(*cell.shape), placement_(*cell.placement), sign_(cell.sign()), part_(cell.part) {}

    /// The ray in the leaf's frame and its segment clipped to the part (a
    /// turned part's world box holds more than the part); false when nothing
    /// of the segment is left.
    bool leafSegment(const Vec3& origin, const Vec3& direction, Vec3& o, Vec3& d, double& t0, double& t1) const {
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(part_, o, d, t0, t1)) return false;
        return t1 > t0;
    }
    void recordShapeHit(CellTraceResult& r, double t, const Vec3& o, const Vec3& d) const {
        recordHit(r, t, shape_, o, d, placement_, sign_);
    }

    Shape shape_;
    LeafPlacement placement_;
    double sign_;  ///< -1 for the complement (a carving operand)
    Box3 part_;    ///< in the leaf's frame
};

class CellAccelerator {
public:
    virtual ~CellAccelerator() = default;
    /// Takes over a cell, or declines (nullopt: the general tracer marches
    /// it). `surfaceDiagonal` is the diagonal of the whole surface's bounds,
    /// the scale of relative tolerances. Called in parallel for many cells.
    virtual std::optional<CellAcceleration> accelerate(const FieldProgram& cellProgram, const Box3& cellBox,
                                                       double surfaceDiagonal) const = 0;
    /// Whether the accelerator marches the whole field in `box` faster as one
    /// cell than as the octree's many, each of which costs a ray a call from
    /// Embree: the surface is then offered `box` (its proven box) alone.
    virtual bool marchesWholeField(const FieldProgram& /*field*/, const Box3& /*box*/) const { return false; }
};

}  // namespace isotrace::geometry
