#include "geometry/tracing/csg_cells.h"

#include <array>
#include <cmath>

#include "geometry/tracing/shape_spans.h"

namespace isotrace::geometry {

namespace {

// Cell programs this small are taken: a ray's spans then fit in fixed
// arrays on the stack (nothing allocated per ray).
constexpr size_t kMaxLeaves = 4, kMaxInstructions = 12;
constexpr int kMaxSpans = 8;

// Where the ray is inside, within the segment [t0, t1]; each end names the
// leaf whose surface it is, or -1 for the segment's own end.
struct Span {
    double enter, leave;
    int enterLeaf, leaveLeaf;
};

// A ray that passes within the trace's resolution of an edge or a point
// where two solids touch (a concave edge of a difference, spheres side by
// side) crosses nothing there: spans and gaps that short, between two
// surfaces, are rounding, not a way out of the solid and back.
struct SpanList {
    std::array<Span, kMaxSpans> spans;
    int count = 0;
    bool overflow = false;
    double resolution = 0.0;  ///< in t

    void push(const Span& s) {
        if (!(s.enter < s.leave)) return;  // a ray touching a surface does not enter
        if (s.enterLeaf >= 0 && s.leaveLeaf >= 0 && !(s.leave - s.enter > resolution)) return;
        if (count == kMaxSpans) overflow = true;
        else spans[count++] = s;
    }
};

void unite(const SpanList& a, const SpanList& b, SpanList& out) {
    out.overflow = a.overflow || b.overflow;
    int i = 0, j = 0;
    while (i < a.count || j < b.count) {
        const Span& next = j == b.count || (i < a.count && a.spans[i].enter <= b.spans[j].enter) ? a.spans[i++] : b.spans[j++];
        if (out.count > 0 && next.enter <= out.spans[out.count - 1].leave + out.resolution) {
            Span& last = out.spans[out.count - 1];
            if (next.leave > last.leave) last.leave = next.leave, last.leaveLeaf = next.leaveLeaf;
        } else {
            out.push(next);
        }
    }
}

void intersect(const SpanList& a, const SpanList& b, SpanList& out) {
    out.overflow = a.overflow || b.overflow;
    int i = 0, j = 0;
    while (i < a.count && j < b.count) {
        const Span &x = a.spans[i], &y = b.spans[j];
        const Span& later = x.enter >= y.enter ? x : y;
        const Span& sooner = x.leave <= y.leave ? x : y;
        out.push({later.enter, sooner.leave, later.enterLeaf, sooner.leaveLeaf});
        if (x.leave <= y.leave) ++i;
        else ++j;
    }
}

void complement(const SpanList& a, double t0, double t1, SpanList& out) {
    out.overflow = a.overflow;
    double from = t0;
    int fromLeaf = -1;
    for (int i = 0; i < a.count; ++i) {
        out.push({from, a.spans[i].enter, fromLeaf, a.spans[i].enterLeaf});
        from = a.spans[i].leave;
        fromLeaf = a.spans[i].leaveLeaf;
    }
    out.push({from, t1, fromLeaf, -1});
}

// One shape of the cell, with what the ray needs of it.
struct CsgLeaf {
    std::variant<SphereField, BoxField, TorusField> shape;
    LeafPlacement placement;
    std::optional<RoundedBoxPieces> boxPieces;  // the pieces of a box that reach the part
};

class CsgCellTracer final : public CellTracer {
public:
    CsgCellTracer(std::vector<FieldInstruction> code, std::vector<CsgLeaf> leaves)
        : code_(std::move(code)), leaves_(std::move(leaves)) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings& settings) const override {
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        std::array<SpanList, kMaxInstructions> slot;
        for (SpanList& list : slot) list.resolution = settings.epsilon / direction.norm();
        for (size_t i = 0; i < code_.size(); ++i) {
            const FieldInstruction& in = code_[i];
            switch (in.op) {
                case FieldOp::Leaf: leafSpans(int(in.a), origin, direction, t0, t1, settings, slot[i], r); break;
                case FieldOp::Min: unite(slot[in.a], slot[in.b], slot[i]); break;
                case FieldOp::Max: intersect(slot[in.a], slot[in.b], slot[i]); break;
                case FieldOp::Negate: complement(slot[in.a], t0, t1, slot[i]); break;
                default: break;  // not taken (see accelerate)
            }
        }
        r.steps += 1;
        const SpanList& solid = slot[code_.size() - 1];
        if (solid.overflow) {
            // More spans than the arrays hold: the general tracer settles it.
            r.complete = false;
            r.t = t0;
            r.restEnd = t1;
            return r;
        }
        for (int i = 0; i < solid.count; ++i) {
            const Span& s = solid.spans[i];
            if (s.enterLeaf >= 0) return hitOn(r, s.enterLeaf, s.enter, true, origin, direction);
            if (s.leaveLeaf >= 0) return hitOn(r, s.leaveLeaf, s.leave, false, origin, direction);
        }
        return r;
    }

private:
    void leafSpans(int index, const Vec3& origin, const Vec3& direction, double t0, double t1,
                   const TraceSettings& settings, SpanList& out, CellTraceResult& r) const {
        const CsgLeaf& leaf = leaves_[size_t(index)];
        Vec3 o, d;
        rayInLeafFrame(leaf.placement, origin, direction, o, d);
        ++r.evaluations;
        double enter, leave;
        if (const auto* sphere = std::get_if<SphereField>(&leaf.shape)) {
            if (sphereSpan(*sphere, o, d, enter, leave))
                out.push({std::max(enter, t0), std::min(leave, t1), enter >= t0 ? index : -1, leave <= t1 ? index : -1});
        } else if (leaf.boxPieces) {
            if (leaf.boxPieces->span(o, d, t0, t1, enter, leave))
                out.push({enter, leave, enter > t0 ? index : -1, leave < t1 ? index : -1});
        } else if (const auto* torus = std::get_if<TorusField>(&leaf.shape)) {
            torusSpans(*torus, index, o, d, t0, t1, settings.epsilon / direction.norm(), out, r);
        }
    }

    // The quartic's roots in the segment, one after another, and between
    // them its sign: a touching root parts no spans.
    static void torusSpans(const TorusField& torus, int index, const Vec3& o, const Vec3& d, double t0, double t1,
                           double tolerance, SpanList& out, CellTraceResult& r) {
        double tc;
        const Monomials<4> quartic = torusQuarticAlongRay(torus, o, d, tc);
        std::array<double, 6> ends;
        int n = 0;
        ends[n++] = t0 - tc;
        for (double from = t0 - tc; n < 5;) {
            BernsteinRootStats stats;
            const auto s = firstBernsteinRoot<4>(quartic, from, t1 - tc, tolerance, &stats);
            r.steps += stats.subdivisions;
            if (!s) break;
            ends[n++] = *s;
            from = *s + 2.0 * tolerance;
            if (!(from < t1 - tc)) break;
        }
        ends[n++] = t1 - tc;
        Span open{};
        bool inside = false;
        for (int k = 0; k + 1 < n; ++k) {
            const bool in = evaluatePolynomial<4>(quartic, 0.5 * (ends[k] + ends[k + 1])) < 0.0;
            if (in && !inside) open = {tc + ends[k], 0.0, k == 0 ? -1 : index, -1};
            if (!in && inside) {
                open.leave = tc + ends[k];
                open.leaveLeaf = index;
                out.push(open);
            }
            inside = in;
        }
        if (inside) {
            open.leave = t1;
            out.push(open);
        }
    }

    CellTraceResult& hitOn(CellTraceResult& r, int index, double t, bool entering, const Vec3& origin,
                           const Vec3& direction) const {
        const CsgLeaf& leaf = leaves_[size_t(index)];
        const Vec3 p = leaf.placement.leafFromWorld(origin + t * direction);
        Vec3 g;
        std::visit([&](const auto& shape) { shape.valueAndGradient(p, g); }, leaf.shape);
        g = worldGradient(leaf.placement, g);
        // The tree's field is plus or minus this leaf's here: entering the
        // solid it falls along the ray, leaving it rises.
        if ((g.dot(direction) > 0.0) == entering) g = -g;
        r.hit = true;
        r.t = t;
        r.gradientKnown = true;
        r.gradient = g;
        return r;
    }

    std::vector<FieldInstruction> code_;
    std::vector<CsgLeaf> leaves_;
};

bool takenShape(const LeafShape& shape) {
    if (std::holds_alternative<SphereField>(shape) || std::holds_alternative<BoxField>(shape)) return true;
    // Spindle tori have an inner sheet in their quartic (torus_cells.h).
    const auto* torus = std::get_if<TorusField>(&shape);
    return torus && torus->minor < torus->major;
}

}  // namespace

std::optional<CellAcceleration> CsgCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                               double) const {
    const std::vector<FieldInstruction>& code = program.instructions();
    if (code.empty() || code.size() > kMaxInstructions) return std::nullopt;
    size_t leafCount = 0;
    for (const FieldInstruction& in : code) {
        if (in.op == FieldOp::Leaf) {
            if (++leafCount > kMaxLeaves || !takenShape(program.leaf(in.a).shape)) return std::nullopt;
        } else if (in.op != FieldOp::Min && in.op != FieldOp::Max && in.op != FieldOp::Negate) {
            return std::nullopt;  // smooth blends and offsets have no exact spans
        }
    }
    CellAcceleration a;
    const Box3 part = shrunkToSurface(box, [&](const Box3& b) { return program.range(b); });
    if (part.isEmpty()) return a;
    // Leaves renumbered in the order the tape meets them.
    std::vector<FieldInstruction> renumbered = code;
    std::vector<CsgLeaf> leaves;
    leaves.reserve(leafCount);
    for (FieldInstruction& in : renumbered) {
        if (in.op != FieldOp::Leaf) continue;
        const FieldLeaf& leaf = program.leaf(in.a);
        CsgLeaf taken{SphereField{}, leaf.placement, std::nullopt};
        if (const auto* sphere = std::get_if<SphereField>(&leaf.shape)) taken.shape = *sphere;
        if (const auto* torus = std::get_if<TorusField>(&leaf.shape)) taken.shape = *torus;
        if (const auto* b = std::get_if<BoxField>(&leaf.shape)) {
            taken.shape = *b;
            const Box3 local = leaf.placement.leafFromWorld(part);
            taken.boxPieces.emplace(*b, local);  // none kept: the box is outside the whole part
        }
        in.a = uint32_t(leaves.size());
        leaves.push_back(std::move(taken));
    }
    a.parts = {part};
    a.tracer = std::make_unique<CsgCellTracer>(std::move(renumbered), std::move(leaves));
    return a;
}

}  // namespace isotrace::geometry
