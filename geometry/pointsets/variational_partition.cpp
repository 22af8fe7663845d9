#include "geometry/pointsets/variational_partition.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "geometry/point_grid.h"
#include "geometry/variational/rbf_solver.h"

namespace isotrace::geometry {

namespace {

struct Cell {
    Vec3 center;
    double half;
    int depth;
};

// The octree's leaves: cells split while they hold more than `most`
// constraints or their ball (radius `support` diagonals) more than
// `mostInBall` (a sparse cell beside a dense sheet), their empty octants
// kept as leaves too (every point of the domain must lie in a leaf, whose
// ball then covers it).
std::vector<Cell> leafCells(const std::vector<Vec3>& positions, const PointGrid& grid, const Cell& root, size_t most,
                            size_t mostInBall, double support, int maxDepth, int& depth) {
    std::vector<Cell> leaves;
    struct Pending {
        Cell cell;
        std::vector<uint32_t> inside;
    };
    std::vector<Pending> stack(1);
    std::vector<uint32_t> inBall;
    stack[0].cell = root;
    stack[0].inside.resize(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) stack[0].inside[i] = uint32_t(i);
    while (!stack.empty()) {
        Pending p = std::move(stack.back());
        stack.pop_back();
        depth = std::max(depth, p.cell.depth);
        bool split = p.inside.size() > most;
        if (!split) {
            grid.within(p.cell.center, support * 2.0 * std::sqrt(3.0) * p.cell.half, inBall);
            split = inBall.size() > mostInBall;
        }
        if (!split || p.cell.depth >= maxDepth) {
            leaves.push_back(p.cell);
            continue;
        }
        std::vector<uint32_t> octant[8];
        for (uint32_t i : p.inside) {
            const Vec3 d = positions[i] - p.cell.center;
            octant[(d.x() >= 0) | ((d.y() >= 0) << 1) | ((d.z() >= 0) << 2)].push_back(i);
        }
        for (int k = 0; k < 8; ++k) {
            const Vec3 offset((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
            stack.push_back({{p.cell.center + p.cell.half * offset, 0.5 * p.cell.half, p.cell.depth + 1}, std::move(octant[k])});
        }
    }
    return leaves;
}

}  // namespace

MpuField fitPartitionedVariationalField(const ConstraintSet& set, PartitionReport* report, const PartitionOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (options.leafConstraints < 1 || options.ballConstraints < 5 || options.mostBallConstraints < options.ballConstraints || !(options.support > 0.5 && options.support <= 4) ||
        options.maxDepth < 1 || !(options.domainMargin >= 0))
        throw FitError("partition options out of range");
    checkConstraints(set);
    const size_t values = set.values.size(), count = values + set.gradients.size();
    std::vector<Vec3> positions(count);
    for (size_t i = 0; i < values; ++i) positions[i] = set.values[i].position;
    for (size_t i = values; i < count; ++i) positions[i] = set.gradients[i - values].position;

    const Box3 box = set.bounds();
    const double size = box.extent().norm();
    const Cell root{box.center(), 0.5 * box.extent().maxCoeff() + options.domainMargin * size, 0};
    const Box3 domain = Box3::around(root.center, root.half);
    PartitionReport r;
    r.constraints = count;
    const PointGrid grid(positions, domain, PointGrid::resolutionFor(count));
    const std::vector<Cell> leaves = leafCells(positions, grid, root, size_t(options.leafConstraints),
                                               size_t(options.mostBallConstraints), options.support, options.maxDepth, r.depth);

    auto isNonZero = [&](uint32_t i) {
        return i < values ? set.values[i].value != 0.0 : set.gradients[i - values].gradient.squaredNorm() > 0.0;
    };
    // Each leaf's interpolant, in parallel: the balls are independent.
    std::vector<MpuLocal> locals(leaves.size());
    std::vector<VariationalField> interpolants(leaves.size());
    std::vector<std::string> failures(leaves.size());
    tbb::parallel_for(size_t(0), leaves.size(), [&](size_t leaf) {
        const Cell& cell = leaves[leaf];
        std::vector<uint32_t> near;
        std::vector<std::pair<double, uint32_t>> byDistance;
        const double baseRadius = options.support * 2.0 * std::sqrt(3.0) * cell.half;
        double radius = baseRadius;
        grid.within(cell.center, radius, near);
        // A ball short of constraints (or singular with them) grows to hold
        // exactly its `wanted` nearest ones: growing the radius by a factor
        // instead can jump from a few dozen to thousands where a ball first
        // reaches a sheet of points, and the solve costs their cube. Its
        // interpolant also meets the nearest non-zero constraints beyond it
        // until a quarter are not zero: inside a solid the nearest are all
        // on its surface (the normals' offset points lie farther), and
        // zeros alone say nothing of the sign. (Constraints beyond a ball
        // may join its fit; those inside it must.)
        size_t wanted = std::max(near.size(), size_t(options.ballConstraints));
        auto nonZeroCount = [&](const std::vector<uint32_t>& list) {
            size_t n = 0;
            for (uint32_t i : list) n += isNonZero(i);
            return n;
        };
        for (bool grow = near.size() < size_t(options.ballConstraints) || nonZeroCount(near) == 0;; grow = true) {
            if (grow) {
                double reach = radius;
                do {
                    reach *= 2.0;
                    grid.within(cell.center, reach, near);
                } while ((near.size() <= wanted || nonZeroCount(near) < wanted / 4) && near.size() < count);
                byDistance.clear();
                for (uint32_t i : near) byDistance.push_back({(positions[i] - cell.center).norm(), i});
                std::sort(byDistance.begin(), byDistance.end());
                const size_t k = std::min(wanted, byDistance.size());
                // Midway to the next one, so the ball holds exactly these.
                radius = k < byDistance.size() ? 0.5 * (byDistance[k - 1].first + byDistance[k].first)
                                               : 1.01 * byDistance.back().first + 1e-9 * size;
                radius = std::max(radius, baseRadius);
                near.clear();
                size_t nonZero = 0;
                for (const auto& [d, i] : byDistance)
                    if (d < radius) near.push_back(i), nonZero += isNonZero(i);
                for (const auto& [d, i] : byDistance)
                    if (nonZero >= wanted / 4) break;
                    else if (d >= radius && isNonZero(i)) near.push_back(i), ++nonZero;
            }
            ConstraintSet local;
            bool nonZero = false;
            for (uint32_t i : near) {
                if (i < values) {
                    local.values.push_back(set.values[i]);
                    nonZero |= set.values[i].value != 0.0;
                } else {
                    local.gradients.push_back(set.gradients[i - values]);
                    nonZero |= set.gradients[i - values].gradient.squaredNorm() > 0.0;
                }
            }
            // Only zeros fit f = 0, a surface everywhere: such a ball grows too.
            std::string failure = "no constraint but zeros reaches it";
            if (nonZero && !local.values.empty()) {
                try {
                    interpolants[leaf] = solveVariationalSystem(local);
                    break;
                } catch (const FitError& e) {
                    failure = e.what();
                }
            }
            if (near.size() >= count) {
                failures[leaf] = failure;
                break;
            }
            wanted = std::max(wanted, near.size()) * 3 / 2;
        }
        locals[leaf].center = cell.center;
        locals[leaf].radius = radius;
        locals[leaf].first = uint32_t(leaf);
        locals[leaf].count = 1;
        locals[leaf].combination = MpuCombination::Interpolant;
    });
    for (size_t leaf = 0; leaf < leaves.size(); ++leaf)
        if (!failures[leaf].empty()) {
            char where[96];
            const Vec3& c = leaves[leaf].center;
            std::snprintf(where, sizeof where, "the local fit around (%.6g, %.6g, %.6g) fails: ", c.x(), c.y(), c.z());
            throw FitError(where + failures[leaf]);
        }
    for (const VariationalField& f : interpolants) {
        const size_t n = f.constraintCount();
        r.largestLocal = std::max(r.largestLocal, n);
        r.meanLocal += double(n) / double(interpolants.size());
    }
    r.locals = interpolants.size();
    MpuField field =
        MpuField::fromParts(domain, options.support, 1e-3 * size, std::move(locals), {}, std::move(interpolants));

    // Residuals of the blend, judged as the dense fit judges its own.
    std::vector<double> residual(count, 0.0);
    tbb::parallel_for(size_t(0), count, [&](size_t i) {
        Vec3 g;
        const double v = field.valueAndGradient(positions[i], g);
        residual[i] = i < values ? std::abs(v - set.values[i].value)
                                 : (g - set.gradients[i - values].gradient).cwiseAbs().maxCoeff();
    });
    const double valueScale = constraintValueScale(set);
    for (double e : residual) r.maxResidual = std::max(r.maxResidual, e);
    char text[200];
    // The background term (MpuField::kBackgroundWeight) alone moves values
    // by about 1e-8 of the constraints' size: judged at 1e-5, not 1e-6.
    if (r.maxResidual > 1e-5 * valueScale) {
        std::snprintf(text, sizeof text, "the fit misses its constraints by up to %.3g (constraint values up to %.3g)",
                      r.maxResidual, valueScale);
        r.warnings.push_back(text);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (report) *report = r;
    return field;
}

}  // namespace isotrace::geometry
