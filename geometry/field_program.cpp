#include "geometry/field_program.h"

#include "geometry/smooth_min.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace isotrace::geometry {

namespace {

size_t leafTerms(const LeafShape& shape) {
    return std::visit(
        [](const auto& s) -> size_t {
            if constexpr (requires { s.termCount(); }) return s.termCount();
            else return 1;
        },
        shape);
}

// Scratch storage, one per thread, grown once: evaluation itself never
// allocates in the steady state.
template <class T>
T* scratch(size_t n) {
    thread_local std::vector<T> storage;
    if (storage.size() < n) storage.resize(std::max<size_t>(n, 64));
    return storage.data();
}

struct ValueAndGradient {
    double value;
    Vec3 gradient;
};

}  // namespace

LeafPlacement LeafPlacement::composed(const Mat3& childFromParentLinear, const Vec3& childFromParentOffset,
                                      double sigma) const {
    LeafPlacement out;
    out.linear = childFromParentLinear * linear;
    out.offset = childFromParentLinear * offset + childFromParentOffset;
    out.valueScale = valueScale * sigma;
    const double norm = Eigen::JacobiSVD<Mat3>(out.linear).singularValues()(0);
    out.gradientScale = out.valueScale * norm;
    out.identity = out.linear.isIdentity(0.0) && out.offset.isZero(0.0) && out.valueScale == 1.0;
    return out;
}

uint32_t FieldProgram::push(const FieldInstruction& instruction, const Box3& slotBounds) {
    code_.push_back(instruction);
    slotBounds_.push_back(slotBounds);
    bounds_ = slotBounds;
    return static_cast<uint32_t>(code_.size() - 1);
}

void FieldProgram::narrowSlotBounds(uint32_t slot, const Box3& b) {
    slotBounds_[slot] = intersection(slotBounds_[slot], b);
    if (slot + 1 == code_.size()) bounds_ = slotBounds_[slot];
}

uint32_t FieldProgram::addLeaf(LeafShape shape, const LeafPlacement& placement) {
    // Bounds in world space: invert the placement (leaf = L world + o).
    Box3 leafBounds = std::visit([](const auto& s) { return s.bounds(); }, shape);
    Box3 worldBounds = leafBounds;
    if (!placement.identity && leafBounds.isFinite() && !leafBounds.isEmpty()) {
        const Mat3 inverse = placement.linear.inverse();
        worldBounds = transformBox(inverse, -inverse * placement.offset, leafBounds);
    }
    evaluationCost_ += leafTerms(shape);
    leaves_.push_back({std::move(shape), placement});
    return push({FieldOp::Leaf, static_cast<uint32_t>(leaves_.size() - 1), 0, 0.0}, worldBounds);
}

uint32_t FieldProgram::addUnary(FieldOp op, uint32_t a, double parameter) {
    Box3 b = slotBounds_[a];
    if (op == FieldOp::Negate) b = Box3::everything();
    // A grown solid (parameter < 0 adds -d) reaches d farther for distance-like fields.
    if (op == FieldOp::AddConstant && parameter < 0) b = b.expanded(-parameter);
    evaluationCost_ += 1;
    return push({op, a, 0, parameter}, b);
}

uint32_t FieldProgram::addBinary(FieldOp op, uint32_t a, uint32_t b, double parameter) {
    Box3 box;
    switch (op) {
        case FieldOp::Min: box = unionOf(slotBounds_[a], slotBounds_[b]); break;
        case FieldOp::SmoothMin:
            // smin >= min - k/4; the margin k covers distance-like operands.
            box = unionOf(slotBounds_[a], slotBounds_[b]).expanded(parameter);
            break;
        case FieldOp::Max:
        case FieldOp::SmoothMax: box = intersection(slotBounds_[a], slotBounds_[b]); break;
        default: box = Box3::everything();
    }
    evaluationCost_ += 1;
    return push({op, a, b, parameter}, box);
}

double FieldProgram::value(const Vec3& p) const { return valueWithLeafValue(p, uint32_t(-1), 0.0); }

double FieldProgram::valueWithLeafValue(const Vec3& p, uint32_t givenLeaf, double givenValue) const {
    double* slot = scratch<double>(code_.size());
    for (size_t i = 0; i < code_.size(); ++i) {
        const FieldInstruction& in = code_[i];
        switch (in.op) {
            case FieldOp::Leaf: {
                if (in.a == givenLeaf) {
                    slot[i] = givenValue;
                    break;
                }
                const FieldLeaf& leaf = leaves_[in.a];
                const Vec3 q = leaf.placement.leafFromWorld(p);
                slot[i] = leaf.placement.valueScale * std::visit([&](const auto& s) { return s.value(q); }, leaf.shape);
                break;
            }
            case FieldOp::Min: slot[i] = std::min(slot[in.a], slot[in.b]); break;
            case FieldOp::Max: slot[i] = std::max(slot[in.a], slot[in.b]); break;
            case FieldOp::Negate: slot[i] = -slot[in.a]; break;
            case FieldOp::SmoothMin: slot[i] = smoothMin(slot[in.a], slot[in.b], in.parameter).value; break;
            case FieldOp::SmoothMax: slot[i] = -smoothMin(-slot[in.a], -slot[in.b], in.parameter).value; break;
            case FieldOp::AddConstant: slot[i] = slot[in.a] + in.parameter; break;
        }
    }
    return slot[code_.size() - 1];
}

double FieldProgram::valueAndSafeDistance(const Vec3& p, double& safeDistance) const {
    safeDistance = 0.0;
    if (code_.size() != 1) return value(p);
    const FieldLeaf& leaf = leaves_[code_[0].a];
    return leaf.placement.valueScale * std::visit(
        [&](const auto& s) {
            const Vec3 q = leaf.placement.leafFromWorld(p);
            if constexpr (requires(double& d) { s.valueAndSafeDistance(q, d); }) {
                double leafDistance = 0.0;
                const double v = s.valueAndSafeDistance(q, leafDistance);
                // |A dp| <= ||A|| |dp|: a world step of d / ||A|| moves at most d in the leaf.
                const double stretch = leaf.placement.gradientScale / leaf.placement.valueScale;
                safeDistance = leafDistance / std::max(stretch, 1e-300);
                return v;
            } else {
                return s.value(q);
            }
        },
        leaf.shape);
}

double FieldProgram::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    ValueAndGradient* slot = scratch<ValueAndGradient>(code_.size());
    for (size_t i = 0; i < code_.size(); ++i) {
        const FieldInstruction& in = code_[i];
        ValueAndGradient& out = slot[i];
        switch (in.op) {
            case FieldOp::Leaf: {
                const FieldLeaf& leaf = leaves_[in.a];
                const LeafPlacement& pl = leaf.placement;
                const Vec3 q = pl.leafFromWorld(p);
                Vec3 g;
                const double v = std::visit([&](const auto& s) { return s.valueAndGradient(q, g); }, leaf.shape);
                out.value = pl.valueScale * v;
                out.gradient = pl.identity ? g : Vec3(pl.valueScale * (pl.linear.transpose() * g));
                break;
            }
            case FieldOp::Min: out = slot[in.a].value <= slot[in.b].value ? slot[in.a] : slot[in.b]; break;
            case FieldOp::Max: out = slot[in.a].value >= slot[in.b].value ? slot[in.a] : slot[in.b]; break;
            case FieldOp::Negate: out = {-slot[in.a].value, -slot[in.a].gradient}; break;
            case FieldOp::SmoothMin: {
                const SmoothMinResult r = smoothMin(slot[in.a].value, slot[in.b].value, in.parameter);
                out = {r.value, r.h * slot[in.a].gradient + (1.0 - r.h) * slot[in.b].gradient};
                break;
            }
            case FieldOp::SmoothMax: {
                const SmoothMinResult r = smoothMin(-slot[in.a].value, -slot[in.b].value, in.parameter);
                out = {-r.value, r.h * slot[in.a].gradient + (1.0 - r.h) * slot[in.b].gradient};
                break;
            }
            case FieldOp::AddConstant: out = {slot[in.a].value + in.parameter, slot[in.a].gradient}; break;
        }
    }
    gradient = slot[code_.size() - 1].gradient;
    return slot[code_.size() - 1].value;
}

void FieldProgram::estimateSlots(const Box3& box, std::vector<BoxEstimate>& slots, bool withLipschitz) const {
    slots.resize(code_.size());
    for (size_t i = 0; i < code_.size(); ++i) {
        const FieldInstruction& in = code_[i];
        BoxEstimate& out = slots[i];
        switch (in.op) {
            case FieldOp::Leaf: {
                const FieldLeaf& leaf = leaves_[in.a];
                const LeafPlacement& pl = leaf.placement;
                const Box3 leafBox = pl.leafFromWorld(box);
                const Interval r = std::visit([&](const auto& s) { return s.range(leafBox); }, leaf.shape);
                const double l =
                    withLipschitz ? std::visit([&](const auto& s) { return s.lipschitz(leafBox); }, leaf.shape) : 0.0;
                // Round-off in the leaf's own arithmetic is absorbed here.
                out.range = widened(pl.valueScale * r);
                out.lipschitz = l * pl.gradientScale * (1.0 + 1e-12);
                break;
            }
            case FieldOp::Min:
            case FieldOp::Max: {
                const BoxEstimate& a = slots[in.a];
                const BoxEstimate& b = slots[in.b];
                const bool isMin = in.op == FieldOp::Min;
                out.range = isMin ? min(a.range, b.range) : max(a.range, b.range);
                // The winning operand alone decides where one dominates the other.
                const bool aWins = isMin ? a.range.hi < b.range.lo : a.range.lo > b.range.hi;
                const bool bWins = isMin ? b.range.hi < a.range.lo : b.range.lo > a.range.hi;
                out.lipschitz = aWins ? a.lipschitz : bWins ? b.lipschitz : std::max(a.lipschitz, b.lipschitz);
                break;
            }
            case FieldOp::Negate: out = {-slots[in.a].range, slots[in.a].lipschitz}; break;
            case FieldOp::SmoothMin: {
                const BoxEstimate& a = slots[in.a];
                const BoxEstimate& b = slots[in.b];
                const double k = in.parameter;
                // Monotone in both operands: the ends come from the ends.
                out.range = {smoothMin(a.range.lo, b.range.lo, k).value, smoothMin(a.range.hi, b.range.hi, k).value};
                out.range = widened(out.range);
                out.lipschitz = std::max(a.lipschitz, b.lipschitz);
                break;
            }
            case FieldOp::SmoothMax: {
                const BoxEstimate& a = slots[in.a];
                const BoxEstimate& b = slots[in.b];
                const double k = in.parameter;
                out.range = {-smoothMin(-a.range.lo, -b.range.lo, k).value, -smoothMin(-a.range.hi, -b.range.hi, k).value};
                out.range = widened(out.range);
                out.lipschitz = std::max(a.lipschitz, b.lipschitz);
                break;
            }
            case FieldOp::AddConstant:
                out = {slots[in.a].range + Interval(in.parameter), slots[in.a].lipschitz};
                out.range = widened(out.range);
                break;
        }
    }
}

BoxEstimate FieldProgram::estimate(const Box3& box) const {
    thread_local std::vector<BoxEstimate> slots;
    estimateSlots(box, slots);
    return slots.back();
}

Interval FieldProgram::range(const Box3& box) const {
    thread_local std::vector<BoxEstimate> slots;
    estimateSlots(box, slots, false);
    return slots.back().range;
}

bool FieldProgram::canPrune() const {
    for (const FieldInstruction& in : code_)
        if (in.op == FieldOp::Min || in.op == FieldOp::Max || in.op == FieldOp::SmoothMin || in.op == FieldOp::SmoothMax)
            return true;
    for (const FieldLeaf& leaf : leaves_)
        if (std::visit([&](const auto& s) { return requires { s.prunedTo(Box3()); }; }, leaf.shape)) return true;
    return false;
}

FieldProgram FieldProgram::prunedTo(const Box3& box) const {
    // Operands are dropped by their ranges alone; a program without binary
    // operations (one blob sum, say) has none to drop and skips even those.
    const bool hasBinary = std::any_of(code_.begin(), code_.end(), [](const FieldInstruction& in) {
        return in.op == FieldOp::Min || in.op == FieldOp::Max || in.op == FieldOp::SmoothMin || in.op == FieldOp::SmoothMax;
    });
    std::vector<BoxEstimate> slots;
    if (hasBinary) estimateSlots(box, slots, false);

    // Which operand each slot reduces to inside the box (itself if none).
    const size_t n = code_.size();
    std::vector<uint32_t> forward(n);
    for (uint32_t i = 0; i < n; ++i) {
        const FieldInstruction& in = code_[i];
        forward[i] = i;
        if (!hasBinary) continue;
        const Interval a = slots[in.a].range;
        const Interval b = in.op == FieldOp::Leaf || in.op == FieldOp::Negate || in.op == FieldOp::AddConstant
                               ? Interval()
                               : slots[in.b].range;
        switch (in.op) {
            case FieldOp::Min:
                if (a.hi < b.lo) forward[i] = forward[in.a];
                else if (b.hi < a.lo) forward[i] = forward[in.b];
                break;
            case FieldOp::Max:
                if (a.lo > b.hi) forward[i] = forward[in.a];
                else if (b.lo > a.hi) forward[i] = forward[in.b];
                break;
            case FieldOp::SmoothMin:
                // h is exactly 1 (or 0) once the operands differ by k or more.
                if (b.lo - a.hi >= in.parameter) forward[i] = forward[in.a];
                else if (a.lo - b.hi >= in.parameter) forward[i] = forward[in.b];
                break;
            case FieldOp::SmoothMax:
                if (a.lo - b.hi >= in.parameter) forward[i] = forward[in.a];
                else if (b.lo - a.hi >= in.parameter) forward[i] = forward[in.b];
                break;
            default: break;
        }
    }

    // Mark what the root needs, then re-emit in order.
    std::vector<bool> live(n, false);
    live[forward[n - 1]] = true;
    for (size_t i = n; i-- > 0;) {
        if (!live[i] || forward[i] != i) continue;
        const FieldInstruction& in = code_[i];
        if (in.op == FieldOp::Leaf) continue;
        live[forward[in.a]] = true;
        if (in.op == FieldOp::Min || in.op == FieldOp::Max || in.op == FieldOp::SmoothMin ||
            in.op == FieldOp::SmoothMax)
            live[forward[in.b]] = true;
    }

    // Sized once: a small scene prunes a program for every cell, and grown
    // vectors left their discarded blocks as fresh pages to fault in.
    FieldProgram out;
    size_t liveSlots = 0, liveLeaves = 0;
    for (uint32_t i = 0; i < n; ++i)
        if (live[i] && forward[i] == i) ++liveSlots, liveLeaves += code_[i].op == FieldOp::Leaf;
    out.code_.reserve(liveSlots);
    out.slotBounds_.reserve(liveSlots);
    out.leaves_.reserve(liveLeaves);
    std::vector<uint32_t> remap(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
        if (!live[i] || forward[i] != i) continue;
        const FieldInstruction& in = code_[i];
        if (in.op == FieldOp::Leaf) {
            const FieldLeaf& leaf = leaves_[in.a];
            LeafShape shape = std::visit(
                [&](const auto& s) -> LeafShape {
                    if constexpr (requires { s.prunedTo(box); }) {
                        return s.prunedTo(leaf.placement.leafFromWorld(box));
                    } else {
                        return s;
                    }
                },
                leaf.shape);
            remap[i] = out.addLeaf(std::move(shape), leaf.placement);
        } else if (in.op == FieldOp::Negate || in.op == FieldOp::AddConstant) {
            remap[i] = out.addUnary(in.op, remap[forward[in.a]], in.parameter);
        } else {
            remap[i] = out.addBinary(in.op, remap[forward[in.a]], remap[forward[in.b]], in.parameter);
        }
    }
    out.bounds_ = bounds_;
    return out;
}

}  // namespace isotrace::geometry
