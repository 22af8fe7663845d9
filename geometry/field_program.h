// A field compiled into a flat instruction list (a "tape"): leaves first,
// operators after their operands, the root last. One loop answers each of the
// four questions a field must answer: value, gradient, the range of values
// over a box, and a bound on the gradient's length over a box. Transforms are
// pushed into the leaves at compile time, so operators never see them.
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <variant>
#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/fields/blobby.h"
#include "geometry/fields/box.h"
#include "geometry/fields/convolution.h"
#include "geometry/fields/ellipsoid.h"
#include "geometry/fields/octahedron.h"
#include "geometry/fields/plane.h"
#include "geometry/fields/polyline_distance.h"
#include "geometry/fields/polynomial.h"
#include "geometry/fields/revolved_profile.h"
#include "geometry/fields/sphere.h"
#include "geometry/fields/sphere_set.h"
#include "geometry/fields/torus.h"
#include "geometry/fields/vdb_level_set.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/variational/variational_field.h"

namespace isotrace::geometry {

/// What a field kind must provide to be a leaf of field programs, in its own
/// frame (LeafPlacement maps the world to it):
/// - value(p) and valueAndGradient(p, gradient): the field, negative inside;
/// - range(box): an interval proven to hold every value over the box;
/// - lipschitz(box): a proven bound on the gradient's length over the box;
/// - bounds(): a box outside which the field is positive.
/// A kind may also provide termCount() (its cost per evaluation, default 1),
/// valueAndSafeDistance(p, distance) (a radius free of zeros, tighter than
/// |f| / lipschitz), and prunedTo(box) (a copy keeping what reaches the box);
/// field programs use them where present. Adding a kind: README.md, "Adding
/// a field kind".
template <class T>
concept LeafField = requires(const T& f, const Vec3& p, Vec3& gradient, const Box3& box) {
    { f.value(p) } -> std::convertible_to<double>;
    { f.valueAndGradient(p, gradient) } -> std::convertible_to<double>;
    { f.range(box) } -> std::convertible_to<Interval>;
    { f.lipschitz(box) } -> std::convertible_to<double>;
    { f.bounds() } -> std::convertible_to<Box3>;
};

/// A fitted field (variational or MPU) as a leaf: shared, not copied, since
/// every octree cell's pruned program holds one.
template <class Field>
struct SharedLeafField {
    std::shared_ptr<const Field> field;

    double value(const Vec3& p) const { return field->value(p); }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const { return field->valueAndGradient(p, gradient); }
    double valueAndSafeDistance(const Vec3& p, double& safe) const { return field->valueAndSafeDistance(p, safe); }
    Interval range(const Box3& box) const { return field->range(box); }
    double lipschitz(const Box3& box) const { return field->lipschitz(box); }
    Box3 bounds() const { return field->bounds(); }
    size_t termCount() const { return field->termCount(); }
};
using VariationalLeafField = SharedLeafField<VariationalField>;
using MpuLeafField = SharedLeafField<MpuField>;

using LeafShape = std::variant<SphereField, BoxField, TorusField, PlaneField, EllipsoidField, OctahedronField,
                               RevolvedProfileField,
                               PolylineDistanceField, PolynomialField, BlobbyField, ConvolutionField,
                               VariationalLeafField, MpuLeafField, VdbLevelSetField, SphereSetField>;

template <class Variant>
struct AllLeafFields;
template <class... Kinds>
struct AllLeafFields<std::variant<Kinds...>> : std::bool_constant<(LeafField<Kinds> && ...)> {};
static_assert(AllLeafFields<LeafShape>::value, "every kind in LeafShape must satisfy LeafField");

/// Where a leaf sits: its shape is evaluated at leafFromWorld(p) and its value
/// multiplied by valueScale (the smallest singular value of the accumulated
/// scaling, which keeps a distance field's Lipschitz constant at 1).
struct LeafPlacement {
    Mat3 linear = Mat3::Identity();
    Vec3 offset = Vec3::Zero();
    double valueScale = 1.0;
    double gradientScale = 1.0;  ///< valueScale * ||linear||_2
    bool identity = true;

    bool operator==(const LeafPlacement&) const = default;
    Vec3 leafFromWorld(const Vec3& p) const { return identity ? p : Vec3(linear * p + offset); }
    /// A box around the image of a world box in the leaf's frame.
    Box3 leafFromWorld(const Box3& box) const { return identity ? box : transformBox(linear, offset, box); }
    /// Placement of a child whose frame is given by parent = A child + t
    /// with value scale sigma (see FieldParser's transform).
    LeafPlacement composed(const Mat3& childFromParentLinear, const Vec3& childFromParentOffset,
                           double sigma) const;
};

struct FieldLeaf {
    LeafShape shape;
    LeafPlacement placement;
};

enum class FieldOp : uint8_t {
    Leaf,        ///< a: leaf index
    Min,         ///< union
    Max,         ///< intersection
    Negate,      ///< complement
    SmoothMin,   ///< parameter: blend radius k (quadratic polynomial smooth minimum)
    SmoothMax,   ///< parameter: blend radius k
    AddConstant  ///< parameter added (offsets: -distance grows the solid)
};

struct FieldInstruction {
    FieldOp op = FieldOp::Leaf;
    uint32_t a = 0, b = 0;
    double parameter = 0.0;
};

/// Range of values and gradient bound of a field over one box.
struct BoxEstimate {
    Interval range;
    double lipschitz = 0.0;
};

class FieldProgram {
public:
    FieldProgram() = default;

    // Construction (used by the parser and by tests). Returns the slot written.
    uint32_t addLeaf(LeafShape shape, const LeafPlacement& placement = {});
    uint32_t addUnary(FieldOp op, uint32_t a, double parameter = 0.0);
    uint32_t addBinary(FieldOp op, uint32_t a, uint32_t b, double parameter = 0.0);
    /// The box outside which the field is positive. Computed by addX; a
    /// description may narrow it.
    void setBounds(const Box3& b) { bounds_ = b; }
    /// Narrows the bounds of one slot's field (a description's "bounds").
    void narrowSlotBounds(uint32_t slot, const Box3& b);

    double value(const Vec3& p) const;
    /// The value with leaf `leaf`'s value (placement included) taken as
    /// `leafValue` instead of evaluated. Every operator is monotone in each
    /// operand, so for a leaf the tape uses once, the values at the two ends
    /// of an interval of the leaf's value bound the program's: a cheap model
    /// of one costly leaf with a proven error certifies the sign.
    double valueWithLeafValue(const Vec3& p, uint32_t leaf, double leafValue) const;
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    /// The value at p and a radius around p free of zeros, when the program
    /// is a single leaf that can say (variational fields); else 0.
    double valueAndSafeDistance(const Vec3& p, double& safeDistance) const;
    BoxEstimate estimate(const Box3& box) const;
    /// The range alone (cheaper: no gradient bounds).
    Interval range(const Box3& box) const;
    /// A program equal to this one everywhere inside `box`, without the
    /// operands that cannot matter there (dominated CSG operands, smooth
    /// blends whose operands are farther apart than the blend radius, blobs
    /// whose support does not reach the box).
    FieldProgram prunedTo(const Box3& box) const;
    /// False when prunedTo can only copy the program: no CSG or blend
    /// operands to drop and no leaf with terms of its own (blobs, segments).
    bool canPrune() const;

    const Box3& bounds() const { return bounds_; }
    bool empty() const { return code_.empty(); }
    /// The leaf, when the whole program is one leaf (as many pruned cell
    /// programs are); else null.
    const FieldLeaf* singleLeaf() const { return code_.size() == 1 ? &leaves_[code_[0].a] : nullptr; }
    /// The leaf when the program is one leaf or its complement (as the
    /// cells of a difference are where only the carving operand is left):
    /// the same surface, with `negated` telling that the gradient flips.
    const FieldLeaf* leafUpToSign(bool& negated) const {
        negated = code_.size() == 2 && code_[0].op == FieldOp::Leaf && code_[1].op == FieldOp::Negate;
        return code_.size() == 1 || negated ? &leaves_[code_[0].a] : nullptr;
    }
    size_t instructionCount() const { return code_.size(); }
    /// The tape, for accelerators that read a program's structure: slot i
    /// holds instruction i's result; a Leaf's `a` indexes leaf().
    const std::vector<FieldInstruction>& instructions() const { return code_; }
    const FieldLeaf& leaf(uint32_t index) const { return leaves_[index]; }
    /// Node evaluations per point: instructions plus the terms inside leaves
    /// (blobs, segments), the cost measure of the benchmarks.
    size_t evaluationCost() const { return evaluationCost_; }

private:
    void estimateSlots(const Box3& box, std::vector<BoxEstimate>& slots, bool withLipschitz = true) const;
    uint32_t push(const FieldInstruction& instruction, const Box3& slotBounds);

    std::vector<FieldInstruction> code_;
    std::vector<FieldLeaf> leaves_;
    std::vector<Box3> slotBounds_;  ///< bounds of each slot's field, for the root's bounds
    Box3 bounds_ = Box3::everything();
    size_t evaluationCost_ = 0;
};

}  // namespace isotrace::geometry
