#include "geometry/meshing/polygonizer.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <unistd.h>

#include "geometry/meshing/mesh_analysis.h"
#include "geometry/meshing/mesh_simplifier.h"

namespace isotrace::geometry {

namespace {

constexpr int kMaxSearchResolution = 256;

double physicalMemory() { return double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE)); }

void checkResolution(int resolution) {
    if (resolution <= 0) throw std::invalid_argument("resolution must be at least 1, found " + std::to_string(resolution));
    const double bytes = estimatePolygonizeBytes(resolution);
    if (resolution > kMaxPolygonizeResolution || bytes > 0.5 * physicalMemory())
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

    int resolution = options.resolution;
    if (resolution != 0) checkResolution(resolution);
    IndexedMesh m;
    if (resolution == 0 && options.tolerance > 0) {
        // Double the grid until marching cubes alone meets the tolerance
        // (half of it for the adaptive mesher, which spends the rest).
        const double target = adaptive ? 0.5 * options.tolerance : options.tolerance;
        // The search stops at kMaxSearchResolution: beyond it a scene load
        // would take minutes; an explicit resolution may go higher.
        for (resolution = 16;; resolution *= 2) {
            m = mesh(field, resolution, adaptive, options.threads);
            if (m.triangles.empty()) break;
            const double reached = measureAccuracy(m, field).maxCentroidDistance;
            if (reached <= target) break;
            if (resolution >= kMaxSearchResolution) {
                result.warnings.push_back("tolerance " + std::to_string(options.tolerance) + " not reached at resolution " +
                                          std::to_string(resolution) + " (largest distance " + std::to_string(reached) +
                                          "); give a resolution to go further");
                break;
            }
        }
    } else {
        if (resolution == 0) resolution = 128;
        m = mesh(field, resolution, adaptive, options.threads);
    }
    result.resolution = resolution;
    if (m.triangles.empty()) {
        result.warnings.push_back("the field has no surface inside its bounds: the mesh is empty");
    } else if (adaptive) {
        SimplifyOptions s;
        // Without a tolerance, keep the accuracy marching cubes reached.
        s.maxDistance = options.tolerance > 0 ? options.tolerance : measureAccuracy(m, field).maxCentroidDistance;
        s.threads = options.threads;
        simplifyMesh(m, field, s);
    }
    result.mesh = std::move(m);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace isotrace::geometry
