#include "geometry/tracing/implicit_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "geometry/variational/patch_tracer.h"

namespace isotrace::geometry {

TraceCounters& threadTraceCounters() {
    thread_local TraceCounters counters;
    return counters;
}

ImplicitSurface::ImplicitSurface(FieldProgram field, const ImplicitSurfaceOptions& options)
    : field_(std::move(field)) {
    bounds_ = field_.bounds();
    if (bounds_.isEmpty()) {
        // No solid anywhere: a surface with no cells.
        settings_.epsilon = options.relativeEpsilon;
        return;
    }
    if (!bounds_.isFinite())
        throw std::invalid_argument("the field is unbounded; give it \"bounds\" to render or polygonize it");
    const double diagonal = bounds_.extent().norm();
    settings_.epsilon = options.relativeEpsilon * diagonal;
    // Pad the root box so that surfaces touching the bounds lie strictly inside.
    const Box3 root = bounds_.expanded(1e-4 * diagonal);
    globalLipschitz_ = field_.estimate(root).lipschitz;

    // Refine level by level, keeping only cells whose range holds zero.
    // Children are tested in parallel (a variational field's range is an
    // O(N) sum) and kept in a fixed order.
    std::vector<Box3> level{root};
    for (int depth = 0; depth < options.maxDepth; ++depth) {
        std::vector<std::array<bool, 8>> keep(level.size());
        tbb::parallel_for(size_t(0), level.size(), [&](size_t i) {
            const Vec3 c = level[i].center();
            for (int k = 0; k < 8; ++k) {
                const Box3 child(level[i].corner(k).cwiseMin(c), level[i].corner(k).cwiseMax(c));
                keep[i][k] = field_.range(child).containsZero();
            }
        });
        std::vector<Box3> next;
        for (size_t i = 0; i < level.size(); ++i) {
            const Vec3 c = level[i].center();
            for (int k = 0; k < 8; ++k)
                if (keep[i][k]) next.emplace_back(level[i].corner(k).cwiseMin(c), level[i].corner(k).cwiseMax(c));
        }
        if (next.size() > options.cellBudget) break;
        level = std::move(next);
    }

    // Each cell's program, bound and (for bare variational fields) local
    // models are independent: build them in parallel, keep them in order.
    struct Built {
        bool keep = false;
        SurfaceCell cell;
        FieldProgram program;
        std::optional<std::vector<VariationalPatch>> models;
        const VariationalLeafField* variational = nullptr;
    };
    std::vector<Built> built(level.size());
    const double patchTolerance = options.patchRelativeTolerance * diagonal;
    tbb::parallel_for(size_t(0), level.size(), [&](size_t i) {
        const Box3& box = level[i];
        if (!field_.range(box).containsZero()) return;
        Built& b = built[i];
        b.keep = true;
        b.cell.box = box;
        b.program = options.pruneCells ? field_.prunedTo(box) : field_;
        b.cell.lipschitz = options.globalLipschitzOnly ? globalLipschitz_ : b.program.estimate(box).lipschitz;
        const FieldLeaf* leaf = b.program.singleLeaf();
        const auto* variational = leaf ? std::get_if<VariationalLeafField>(&leaf->shape) : nullptr;
        if (variational && options.variationalPatches) {
            const Box3 leafBox = leaf->placement.identity
                                     ? box
                                     : transformBox(leaf->placement.linear, leaf->placement.offset, box);
            // Tolerance in the leaf's values: world values are valueScale times them.
            b.models = buildSurfaceModels(*variational->field, leafBox, patchTolerance / leaf->placement.valueScale);
            b.variational = variational;
            // A cell its models prove empty is no cell at all.
            if (b.models) b.keep = !b.models->empty();
        }
    });
    for (Built& b : built) {
        if (!b.keep) continue;
        b.cell.program = static_cast<uint32_t>(programs_.size());
        programs_.push_back(std::move(b.program));
        if (!b.models) {
            cells_.push_back(b.cell);
            continue;
        }
        const LeafPlacement& placement = programs_.back().singleLeaf()->placement;
        const Mat3 worldFromLeaf = placement.identity ? Mat3::Identity() : Mat3(placement.linear.inverse());
        for (VariationalPatch& model : *b.models) {
            SurfaceCell cell = b.cell;
            if (placement.identity) {
                cell.box = model.box;
            } else {
                // The world box around the model's box, within the octree cell.
                const Box3 around = transformBox(worldFromLeaf, -(worldFromLeaf * placement.offset), model.box);
                cell.box = Box3(around.lower.cwiseMax(b.cell.box.lower), around.upper.cwiseMin(b.cell.box.upper));
            }
            cell.variational = static_cast<int32_t>(variationalCells_.size());
            variationalCells_.push_back({std::move(model), b.variational->field.get(), placement});
            cells_.push_back(cell);
        }
    }
}

TraceResult ImplicitSurface::intersectCell(uint32_t index, const Vec3& origin, const Vec3& direction, double tNear,
                                           double tFar) const {
    const SurfaceCell& cell = cells_[index];
    double t0 = tNear, t1 = tFar;
    if (!clipRayToBox(cell.box, origin, direction, t0, t1)) return {};
    const FieldProgram& program = programs_[cell.program];
    TraceResult r = cell.variational >= 0 ? traceModel(cell, origin, direction, t0, t1)
                                          : sphereTrace(program, cell.lipschitz, origin, direction, t0, t1, settings_);
    TraceCounters& counters = threadTraceCounters();
    counters.steps += r.steps;
    counters.evaluations += r.evaluations;
    // Hits exactly at tNear belong to the caller's previous surface.
    if (r.hit && !(r.t > tNear && r.t < tFar)) r.hit = false;
    return r;
}

TraceResult ImplicitSurface::traceModel(const SurfaceCell& cell, const Vec3& origin, const Vec3& direction, double t0,
                                        double t1) const {
    // Trace in the leaf's frame: an affine map keeps the ray's t.
    const VariationalCell& v = variationalCells_[cell.variational];
    const Vec3 o = v.placement.leafFromWorld(origin);
    const Vec3 d = v.placement.identity ? direction : Vec3(v.placement.linear * direction);
    // The model holds inside its own box only.
    if (!v.placement.identity && !clipRayToBox(v.model.box, o, d, t0, t1)) return {};
    const PatchTraceResult p = tracePatch(v.model, *v.field, o, d, t0, t1, settings_.epsilon / direction.norm());
    TraceResult r;
    r.steps = p.steps + p.exactEvaluations;
    r.evaluations =
        uint64_t(p.steps) * VariationalPatch::kMonomials + uint64_t(p.exactEvaluations) * v.field->termCount();
    if (!p.complete) {
        const TraceResult rest =
            sphereTrace(programs_[cell.program], cell.lipschitz, origin, direction, p.t, t1, settings_);
        r.hit = rest.hit;
        r.t = rest.t;
        r.steps += rest.steps;
        r.evaluations += rest.evaluations;
        return r;
    }
    r.hit = p.hit;
    r.t = p.t;
    // grad of valueScale f(A x + b) is valueScale A^T grad f.
    r.gradientKnown = p.hit;
    r.gradient = v.placement.valueScale *
                 (v.placement.identity ? p.gradient : Vec3(v.placement.linear.transpose() * p.gradient));
    return r;
}

TraceResult ImplicitSurface::intersect(const Vec3& origin, const Vec3& direction, double tNear, double tFar) const {
    TraceResult best;
    best.t = tFar;
    int steps = 0;
    for (uint32_t i = 0; i < cells_.size(); ++i) {
        const TraceResult r = intersectCell(i, origin, direction, tNear, best.t);
        steps += r.steps;
        if (r.hit && r.t < best.t) best = r;
    }
    best.steps = steps;
    if (!best.hit) best.t = 0;
    return best;
}

Vec3 ImplicitSurface::normal(const Vec3& p) const {
    Vec3 g;
    field_.valueAndGradient(p, g);
    const double n = g.norm();
    return n > 0 ? Vec3(g / n) : Vec3(0, 1, 0);
}

}  // namespace isotrace::geometry
