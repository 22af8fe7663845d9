#include "geometry/tracing/implicit_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "geometry/tracing/variational_cells.h"

namespace isotrace::geometry {

std::vector<std::shared_ptr<const CellAccelerator>> defaultCellAccelerators() {
    return {std::make_shared<VariationalCellAccelerator>()};
}

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
    // Each cell carries its field pruned to its box (exact there), so a
    // child's range costs what its neighbourhood holds, not the whole field:
    // 1,001 blobs no longer cost 1,001 kernel ranges per cell at every
    // level. Without pruning, children share their parent's program.
    // Children are tested in parallel (a variational field's range is an
    // O(N) sum) and kept in a fixed order.
    using Program = std::shared_ptr<const FieldProgram>;
    std::vector<Box3> level{root};
    std::vector<Program> programs{std::make_shared<const FieldProgram>(field_)};
    for (int depth = 0; depth < options.maxDepth; ++depth) {
        std::vector<std::array<Program, 8>> children(level.size());
        tbb::parallel_for(size_t(0), level.size(), [&](size_t i) {
            const Vec3 c = level[i].center();
            for (int k = 0; k < 8; ++k) {
                const Box3 child(level[i].corner(k).cwiseMin(c), level[i].corner(k).cwiseMax(c));
                if (!programs[i]->range(child).containsZero()) continue;
                children[i][k] = options.pruneCells ? std::make_shared<const FieldProgram>(programs[i]->prunedTo(child))
                                                    : programs[i];
            }
        });
        std::vector<Box3> next;
        std::vector<Program> nextPrograms;
        for (size_t i = 0; i < level.size(); ++i) {
            const Vec3 c = level[i].center();
            for (int k = 0; k < 8; ++k)
                if (children[i][k]) {
                    next.emplace_back(level[i].corner(k).cwiseMin(c), level[i].corner(k).cwiseMax(c));
                    nextPrograms.push_back(std::move(children[i][k]));
                }
        }
        if (next.size() > options.cellBudget) break;
        level = std::move(next);
        programs = std::move(nextPrograms);
    }

    // Each cell's program, bound and acceleration (local models for bare
    // variational fields) are independent: build them in parallel, keep
    // them in order.
    struct Built {
        bool keep = false;
        SurfaceCell cell;
        FieldProgram program;
        std::optional<CellAcceleration> acceleration;
    };
    std::vector<Built> built(level.size());
    tbb::parallel_for(size_t(0), level.size(), [&](size_t i) {
        const Box3& box = level[i];
        if (!programs[i]->range(box).containsZero()) return;
        Built& b = built[i];
        b.keep = true;
        b.cell.box = box;
        b.program = *programs[i];
        b.cell.lipschitz = options.globalLipschitzOnly ? globalLipschitz_ : b.program.estimate(box).lipschitz;
        for (const auto& accelerator : options.cellAccelerators) {
            b.acceleration = accelerator->accelerate(b.program, box, diagonal);
            if (b.acceleration) break;
        }
        // A cell its accelerator proves empty is no cell at all.
        if (b.acceleration) b.keep = !b.acceleration->parts.empty();
    });
    for (Built& b : built) {
        if (!b.keep) continue;
        b.cell.program = static_cast<uint32_t>(programs_.size());
        programs_.push_back(std::move(b.program));
        if (!b.acceleration) {
            cells_.push_back(b.cell);
            continue;
        }
        const auto tracer = static_cast<int32_t>(tracers_.size());
        tracers_.push_back(std::move(b.acceleration->tracer));
        for (uint32_t part = 0; part < b.acceleration->parts.size(); ++part) {
            SurfaceCell cell = b.cell;
            cell.box = b.acceleration->parts[part];
            cell.tracer = tracer;
            cell.part = part;
            cells_.push_back(cell);
        }
    }
}

size_t ImplicitSurface::acceleratedCellCount() const {
    size_t n = 0;
    for (const SurfaceCell& c : cells_) n += c.tracer >= 0;
    return n;
}

TraceResult ImplicitSurface::intersectCell(uint32_t index, const Vec3& origin, const Vec3& direction, double tNear,
                                           double tFar) const {
    const SurfaceCell& cell = cells_[index];
    double t0 = tNear, t1 = tFar;
    if (!clipRayToBox(cell.box, origin, direction, t0, t1)) return {};
    const FieldProgram& program = programs_[cell.program];
    TraceResult r;
    if (cell.tracer < 0) {
        r = sphereTrace(program, cell.lipschitz, origin, direction, t0, t1, settings_);
    } else {
        const CellTraceResult a = tracers_[cell.tracer]->trace(cell.part, origin, direction, t0, t1, settings_);
        r = a;
        if (!a.complete) {
            // The accelerator gave up: the general tracer settles the rest.
            const TraceResult rest = sphereTrace(program, cell.lipschitz, origin, direction, a.t, a.restEnd, settings_);
            r.hit = rest.hit;
            r.t = rest.t;
            r.steps += rest.steps;
            r.evaluations += rest.evaluations;
        }
    }
    TraceCounters& counters = threadTraceCounters();
    counters.steps += r.steps;
    counters.evaluations += r.evaluations;
    // Hits exactly at tNear belong to the caller's previous surface.
    if (r.hit && !(r.t > tNear && r.t < tFar)) r.hit = false;
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
