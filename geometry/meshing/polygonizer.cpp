#include "geometry/meshing/polygonizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "geometry/meshing/mesh_analysis.h"
#include "geometry/meshing/mesh_refiner.h"
#include "geometry/meshing/mesh_simplifier.h"
#include "geometry/physical_memory.h"

namespace isotrace::geometry {

namespace {

constexpr int kMaxSearchResolution = 256;
/// The adaptive mesher extracts on the coarsest grid whose marching cubes
/// comes within this factor of the tolerance: one halving of the cell, for
/// a smooth surface.
constexpr double kAdaptiveReach = 4.0;
/// Refinement leaves edges shorter than this fraction of an extraction cell.
constexpr double kMinEdgeFraction = 1.0 / 64.0;

void checkResolution(int resolution) {
    if (resolution <= 0) throw std::invalid_argument("resolution must be at least 1, found " + std::to_string(resolution));
    const double bytes = estimatePolygonizeBytes(resolution);
    if (resolution > kMaxPolygonizeResolution || bytes > 0.5 * physicalMemoryBytes())
        throw std::invalid_argument("resolution " + std::to_string(resolution) + " needs about " +
                                    std::to_string(bytes / double(1 << 30)) +
                                    " GiB for a surface as large as its bounding box's faces; the limit is " +
                                    std::to_string(kMaxPolygonizeResolution) + " and half of this machine's memory");
}

IndexedMesh mesh(const FieldProgram& field, int resolution, bool sharp, int threads) {
    MarchingCubesOptions o;
    o.resolution = resolution;
    o.sharpFeatures = sharp;
    o.threads = threads;
    return marchingCubes(field, field.bounds(), o);
}

}  // namespace

double estimatePolygonizeBytes(int resolution) {
    // A surface as large as the six faces of its box crosses about 6 R^2
    // cells; about 2 triangles and 1 vertex each; triangles take 12 bytes,
    // vertices 48 (position and normal), and welding about as much again.
    const double cells = 6.0 * double(resolution) * double(resolution);
    return cells * (2 * 12 + 48) * 2;
}

Polygonization polygonize(const FieldProgram& field, const PolygonizeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const Box3 bounds = field.bounds();
    if (!bounds.isFinite())
        throw std::invalid_argument("the field is unbounded; give it \"bounds\" to polygonize it");
    if (options.tolerance < 0 || !std::isfinite(options.tolerance))
        throw std::invalid_argument("tolerance must be a positive distance");
    Polygonization result;
    if (bounds.isEmpty()) {
        result.warnings.push_back("the field has no surface inside its bounds: the mesh is empty");
        return result;
    }
    const bool adaptive = options.method == PolygonizeMethod::Adaptive;
    const auto stageStart = [] { return std::chrono::steady_clock::now(); };
    const auto secondsSince = [](auto t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };

    int resolution = options.resolution;
    if (resolution != 0) checkResolution(resolution);
    IndexedMesh m;
    double tolerance = options.tolerance;
    const auto extraction = stageStart();
    if (resolution == 0 && tolerance > 0) {
        // Double the grid until marching cubes alone meets the tolerance (or,
        // for the adaptive mesher, whose refinement takes faces the rest of
        // the way, comes within kAdaptiveReach of it).
        const double target = adaptive ? kAdaptiveReach * tolerance : tolerance;
        // The search stops at kMaxSearchResolution: beyond it a scene load
        // would take minutes; an explicit resolution may go higher.
        for (resolution = 16;; resolution *= 2) {
            m = mesh(field, resolution, adaptive, options.threads);
            if (m.triangles.empty()) break;
            const double reached = measureAccuracy(m, field).maxCentroidDistance;
            if (reached <= target) break;
            if (resolution >= kMaxSearchResolution) {
                if (adaptive) break;  // refinement takes it on
                result.warnings.push_back("tolerance " + std::to_string(tolerance) + " not reached at resolution " +
                                          std::to_string(resolution) + " (largest distance " + std::to_string(reached) +
                                          "); give a resolution to go further");
                break;
            }
        }
        result.extractionResolution = resolution;
    } else {
        if (resolution == 0) resolution = 128;
        // Given a tolerance, the adaptive mesher extracts on half the grid
        // and refines to it. Without one its target is what marching cubes
        // reaches on the whole grid, which only marching cubes there can
        // tell (on the tangle, 64^3 is 12 times less accurate than 128^3,
        // 256^3 4 times more than 128^3): it extracts there and simplifies.
        result.extractionResolution = adaptive && tolerance > 0 ? std::max(resolution / 2, 1) : resolution;
        m = mesh(field, result.extractionResolution, adaptive, options.threads);
        if (adaptive && tolerance == 0 && !m.triangles.empty())
            tolerance = measureAccuracy(m, field).maxCentroidDistance;
    }
    result.extractionSeconds = secondsSince(extraction);
    result.resolution = resolution;
    if (m.triangles.empty()) {
        result.warnings.push_back("the field has no surface inside its bounds: the mesh is empty");
    } else if (adaptive) {
        // Refinement with a tolerance only: without one the grid is the whole
        // one and already meets it.
        if (options.tolerance > 0) {
            const auto refinement = stageStart();
            const double cell = bounds.extent().maxCoeff() / result.extractionResolution;
            const RefineStatistics refined =
                refineMesh(m, field, {.maxDistance = tolerance, .minEdgeLength = kMinEdgeFraction * cell, .threads = options.threads});
            if (refined.facesBeyond > 0)
                result.warnings.push_back(std::to_string(refined.facesBeyond) +
                                          " faces stay farther than the tolerance " + std::to_string(tolerance) +
                                          " from the surface: the field is not smooth there, or its gradient nearly "
                                          "vanishes (refinement stops at edges of 1/" +
                                          std::to_string(int(1 / kMinEdgeFraction)) + " of a cell)");
            result.refinementSeconds = secondsSince(refinement);
        }
        const auto simplification = stageStart();
        SimplifyOptions s;
        s.maxDistance = tolerance;
        s.threads = options.threads;
        simplifyMesh(m, field, s);
        result.simplificationSeconds = secondsSince(simplification);
    }
    result.mesh = std::move(m);
    result.seconds = secondsSince(start);
    return result;
}

}  // namespace isotrace::geometry
