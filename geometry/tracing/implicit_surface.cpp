#include "geometry/tracing/implicit_surface.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "geometry/tracing/blob_cells.h"
#include "geometry/tracing/box_cells.h"
#include "geometry/tracing/csg_cells.h"
#include "geometry/tracing/variational_csg_cells.h"
#include "geometry/tracing/polynomial_cells.h"
#include "geometry/tracing/sphere_cells.h"
#include "geometry/tracing/sphere_set_cells.h"
#include "geometry/tracing/torus_cells.h"
#include "geometry/tracing/vdb_cells.h"
#include "geometry/tracing/mpu_cells.h"
#include "geometry/tracing/partitioned_variational_cells.h"
#include "geometry/tracing/variational_cells.h"

namespace isotrace::geometry {

std::vector<std::shared_ptr<const CellAccelerator>> defaultCellAccelerators() {
    return {std::make_shared<VariationalCellAccelerator>(), std::make_shared<VariationalCsgCellAccelerator>(),
            std::make_shared<MpuCellAccelerator>(), std::make_shared<PartitionedVariationalCellAccelerator>(),
            std::make_shared<BlobCellAccelerator>(), std::make_shared<PolynomialCellAccelerator>(),
            std::make_shared<SphereCellAccelerator>(), std::make_shared<SphereSetCellAccelerator>(),
            std::make_shared<TorusCellAccelerator>(),
            std::make_shared<BoxCellAccelerator>(), std::make_shared<VdbCellAccelerator>(),
            std::make_shared<CsgCellAccelerator>()};
}

TraceCounters& threadTraceCounters() {
    thread_local TraceCounters counters;
    return counters;
}

namespace {

// A domain is tightened only when the proven box holds less than this
// fraction of its volume: a second refinement costs as much as the first.
constexpr double kTighteningVolumeRatio = 0.75;

struct RefinedLevel {
    std::vector<Box3> boxes;
    std::vector<std::shared_ptr<FieldProgram>> programs;
    std::vector<uint8_t> final;  ///< not split further (see refineCells)
};

// Cells of two combined distance-bounded primitives (up to four
// instructions: a difference) stop splitting one level deeper than those
// of one (ImplicitSurfaceOptions::distanceCellDepth).
constexpr size_t kSmallDistanceProgram = 4;

// Cells over sphere sets (fields/sphere_set.h) refine until a ray pays at
// most this many spheres in each (sphereSetCellCost), as deep as
// kSetMaxDepth and to a budget that grows with the set: a cell then costs
// a ray what it holds, not the set.
constexpr size_t kSetMembersPerCell = 128;
constexpr int kSetMaxDepth = 12;


// Refine level by level, keeping only cells whose range holds zero. Each
// cell carries its field pruned to its box (exact there), so a child's
// range costs what its neighbourhood holds, not the whole field: 1,001
// blobs no longer cost 1,001 kernel ranges per cell at every level. Without
// pruning, children share their parent's program. Children are tested in
// parallel (a variational field's range is an O(N) sum) and kept in a fixed
// order.
RefinedLevel refineCells(const Box3& root, const FieldProgram& field, const ImplicitSurfaceOptions& options) {
    using Program = std::shared_ptr<FieldProgram>;
    RefinedLevel level{{root}, {std::make_shared<FieldProgram>(field)}, {0}};
    const size_t members = sphereSetCellCost(field, root);
    const int depthLimit = members > kSetMembersPerCell ? std::max(options.maxDepth, kSetMaxDepth) : options.maxDepth;
    const size_t budget = std::max(options.cellBudget, 2 * members);
    for (int depth = 0; depth < depthLimit; ++depth) {
        // The children that may hold surface, counted before any is pruned:
        // a level over budget is dropped, and pruning it first (the 1,001
        // blobs' 42,000 programs) was most of that scene's page faults.
        std::vector<uint8_t> holding(level.boxes.size(), 0);
        tbb::parallel_for(size_t(0), level.boxes.size(), [&](size_t i) {
            if (level.final[i]) return;
            const FieldProgram& program = *level.programs[i];
            for (int k = 0; k < 8; ++k)
                if (program.range(level.boxes[i].octant(k)).containsZero()) holding[i] |= uint8_t(1u << k);
        });
        size_t count = 0;
        for (size_t i = 0; i < level.boxes.size(); ++i)
            count += level.final[i] ? 1 : size_t(std::popcount(unsigned(holding[i])));
        if (count > budget) break;
        std::vector<std::array<Program, 8>> children(level.boxes.size());
        tbb::parallel_for(size_t(0), level.boxes.size(), [&](size_t i) {
            const FieldProgram& program = *level.programs[i];
            for (int k = 0; k < 8; ++k) {
                if (!(holding[i] & (1u << k))) continue;
                // A program with nothing to prune (one primitive) is shared,
                // not copied: copies were most of a small scene's start-up.
                children[i][k] = options.pruneCells && program.canPrune()
                                     ? std::make_shared<FieldProgram>(program.prunedTo(level.boxes[i].octant(k)))
                                     : level.programs[i];
            }
        });
        RefinedLevel next;
        for (size_t i = 0; i < level.boxes.size(); ++i) {
            if (level.final[i]) {
                next.boxes.push_back(level.boxes[i]);
                next.programs.push_back(level.programs[i]);  // shared: `level` stands if `next` is over budget
                next.final.push_back(1);
                continue;
            }
            for (int k = 0; k < 8; ++k)
                if (children[i][k]) {
                    next.boxes.push_back(level.boxes[i].octant(k));
                    next.programs.push_back(std::move(children[i][k]));
                    next.final.push_back(0);
                }
        }
        // A cell whose field is a distance bound there (Lipschitz 1, to the
        // estimates' safety margin) and small is final: sphere tracing
        // already steps by its value, and smaller cells would not tighten the
        // bound; they would only prune, which pays for programs of more than
        // two primitives.
        if (depth + 1 >= options.distanceCellDepth)
            tbb::parallel_for(size_t(0), next.boxes.size(), [&](size_t i) {
                const FieldProgram& program = *next.programs[i];
                const size_t allowed = depth + 1 >= options.distanceCellDepth + 1 ? kSmallDistanceProgram : 1;
                if (!next.final[i] && program.instructionCount() <= allowed &&
                    sphereSetCellCost(program, next.boxes[i]) <= kSetMembersPerCell &&
                    program.estimate(next.boxes[i]).lipschitz <= 1.0 + 1e-9)
                    next.final[i] = 1;
            });
        // Past the usual depth only cells over many spheres refine on.
        if (depth + 1 >= options.maxDepth)
            for (size_t i = 0; i < next.boxes.size(); ++i)
                if (sphereSetCellCost(*next.programs[i], next.boxes[i]) <= kSetMembersPerCell) next.final[i] = 1;
        level = std::move(next);
        if (std::all_of(level.final.begin(), level.final.end(), [](uint8_t f) { return f != 0; })) break;
    }
    return level;
}

}  // namespace

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
    Box3 root = bounds_.expanded(1e-4 * diagonal);
    globalLipschitz_ = field_.estimate(root).lipschitz;

    // A loose domain (the tangle's preset box is +-3 around a surface within
    // +-2.27) would cost every ray coarser cells and looser bounds. The
    // cells that survive refinement hold every zero the interval ranges
    // cannot exclude, so their union is a proven box for the surface:
    // when it is clearly smaller, refine again from it.
    RefinedLevel level = refineCells(root, field_, options);
    Box3 tight;
    for (const Box3& box : level.boxes) tight.extend(box);
    const bool tighten = !tight.isEmpty() && tight.extent().cwiseQuotient(root.extent()).prod() < kTighteningVolumeRatio;
    if (tighten) root = tight.expanded(1e-4 * tight.extent().norm());
    // An accelerator that marches the whole field best as one cell (a bare
    // polynomial) is offered the proven box alone.
    const bool whole = !tight.isEmpty() &&
                       std::any_of(options.cellAccelerators.begin(), options.cellAccelerators.end(),
                                   [&](const auto& accelerator) { return accelerator->marchesWholeField(field_, root); });
    if (whole) level = {{root}, {std::make_shared<FieldProgram>(field_)}, {1}};
    else if (tighten) level = refineCells(root, field_, options);
    refinementRoot_ = root;

    // Each cell's program, bound and acceleration (local models for bare
    // variational fields) are independent: build them in parallel, keep
    // them in order.
    struct Built {
        bool keep = false;
        SurfaceCell cell;
        std::optional<CellAcceleration> acceleration;
    };
    std::vector<Built> built(level.boxes.size());
    tbb::parallel_for(size_t(0), level.boxes.size(), [&](size_t i) {
        Built& b = built[i];
        const FieldProgram& program = *level.programs[i];
        Box3 box = level.boxes[i];
        for (const auto& accelerator : options.cellAccelerators) {
            b.acceleration = accelerator->accelerate(program, box, diagonal);
            if (b.acceleration) break;
        }
        if (b.acceleration) {
            // An accelerated cell carves its own parts (and proves a cell
            // without any empty); shrinking first costs range tests that
            // are O(N) for a variational field, and made the hand slower.
            if (b.acceleration->parts.empty()) return;
        } else {
            // A cell that hugs its surface marches with the bound of the
            // region the surface is in, not of the cell's far corners (the
            // tangle's gradient grows as x^3 away from it).
            box = shrunkToSurface(box, [&program](const Box3& b) { return program.range(b); });
            if (box.isEmpty()) return;
        }
        b.keep = true;
        b.cell.box = box;
        // Over the margin a segment starts before the cell too (intersectCell).
        b.cell.lipschitz = options.globalLipschitzOnly ? globalLipschitz_
                                                       : program.estimate(box.expanded(settings_.epsilon)).lipschitz;
    });
    // The cells are counted first: an MPU surface has close to a million,
    // and a growing vector would hold its old and new copies at once.
    size_t cellCount = 0;
    for (const Built& b : built)
        if (b.keep) cellCount += b.acceleration ? b.acceleration->parts.size() : 1;
    cells_.reserve(cellCount);
    // Cells that share a program (nothing to prune) keep one copy of it.
    std::unordered_map<const FieldProgram*, uint32_t> programIndex;
    for (size_t i = 0; i < built.size(); ++i) {
        Built& b = built[i];
        if (!b.keep) continue;
        const auto [it, added] = programIndex.emplace(level.programs[i].get(), uint32_t(programs_.size()));
        if (added) {
            // A program the cell holds alone is moved, not copied.
            if (level.programs[i].use_count() == 1) programs_.push_back(std::move(*level.programs[i]));
            else programs_.push_back(*level.programs[i]);
        }
        b.cell.program = it->second;
        if (!b.acceleration) {
            cells_.push_back(b.cell);
            continue;
        }
        // The previous cell's tracer takes this cell's parts over where it
        // can (CellTracer::absorb): cells are offered in order, so the
        // cells of one field end up sharing one tracer.
        const std::optional<CellTracer::Absorbed> absorbed =
            tracers_.empty() ? std::nullopt : tracers_.back()->absorb(*b.acceleration);
        if (!absorbed) tracers_.push_back(std::move(b.acceleration->tracer));
        const auto tracer = static_cast<int32_t>(tracers_.size() - 1);
        const uint32_t firstPart = absorbed ? absorbed->firstPart : 0;
        for (uint32_t part = 0; part < b.acceleration->parts.size(); ++part) {
            SurfaceCell cell = b.cell;
            cell.box = b.acceleration->parts[part];
            cell.tracer = tracer;
            cell.part = firstPart + part;
            if (!b.acceleration->bands.empty()) cell.band = b.acceleration->bands[part];
            if (!b.acceleration->payloads.empty()) {
                cell.payload = b.acceleration->payloads[part];
                if (absorbed) cell.payload.firstTerm += absorbed->termOffset;
            }
            cells_.push_back(cell);
        }
        b.acceleration.reset();  // its parts, bands and payloads are the cells' now
    }
}

size_t ImplicitSurface::acceleratedCellCount() const {
    size_t n = 0;
    for (const SurfaceCell& c : cells_) n += c.tracer >= 0;
    return n;
}

TraceResult ImplicitSurface::intersectCell(uint32_t index, const Vec3& origin, const Vec3& direction, double tNear,
                                           double tFar, bool anyHit) const {
    const SurfaceCell& cell = cells_[index];
    double t0 = tNear, t1 = tFar;
    if (!clipRayToBox(cell.box, origin, direction, t0, t1)) return {};
    // A surface on the face the ray enters the cell by lies inside no cell:
    // the segment starts a resolution step before the face (the cell's
    // Lipschitz bound covers that margin), and a crossing there is reported
    // on the face. Not for a ray through an edge or a corner that only
    // touches the cell: the cells it passes through see that point, and
    // the margin would reach into them and see the solid the ray comes
    // from as a surface.
    const double resolution = settings_.epsilon / direction.norm();
    const double entry = t0;
    if (t0 > tNear && t1 - t0 >= resolution && (cell.tracer < 0 || tracers_[cell.tracer]->tracesFromBeforeItsPart()))
        t0 = std::max(tNear, t0 - resolution);
    const FieldProgram& program = programs_[cell.program];
    TraceResult r;
    TraceSettings settings = settings_;
    settings.anyHit = anyHit;
    if (cell.tracer < 0) {
        r = sphereTrace(program, cell.lipschitz, origin, direction, t0, t1, settings);
    } else {
        const CellTraceResult a =
            tracers_[cell.tracer]->trace(cell.part, cell.band, cell.payload, origin, direction, t0, t1, settings);
        r = a;
        if (!a.complete) {
            // The accelerator gave up: the general tracer settles the rest.
            const TraceResult rest = sphereTrace(program, cell.lipschitz, origin, direction, a.t, a.restEnd, settings);
            r.hit = rest.hit;
            r.t = rest.t;
            r.steps += rest.steps;
            r.evaluations += rest.evaluations;
        }
    }
    TraceCounters& counters = threadTraceCounters();
    counters.steps += r.steps;
    counters.evaluations += r.evaluations;
    if (r.hit) r.t = std::max(r.t, entry);
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
