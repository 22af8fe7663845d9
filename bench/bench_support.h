// Helpers shared by the benchmarks: timing medians and procedural scenes.
#pragma once

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "renderer/scene.h"

namespace isotrace::bench {

/// The middle of `values` (the upper middle of an even count).
inline double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

/// Median wall time in seconds of `runs` calls.
inline double medianSeconds(int runs, const std::function<void()>& work) {
    std::vector<double> times;
    for (int i = 0; i < runs; ++i) {
        const auto start = std::chrono::steady_clock::now();
        work();
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return median(std::move(times));
}

/// Medians of two pieces of work run alternately: a ratio of the two then
/// sees the same drift of a shared machine.
inline std::pair<double, double> interleavedMedianSeconds(int runs, const std::function<void()>& first,
                                                          const std::function<void()>& second) {
    std::vector<double> a, b;
    for (int i = 0; i < runs; ++i) {
        for (auto [work, times] : {std::pair{&first, &a}, std::pair{&second, &b}}) {
            const auto start = std::chrono::steady_clock::now();
            (*work)();
            times->push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        }
    }
    return {median(std::move(a)), median(std::move(b))};
}

/// A file of this name in the system's temporary folder (benches' inputs made on the fly).
inline std::string temporaryPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / name).string();
}

/// A torus tessellated into 2 * rings * segments triangles.
inline TriangleMesh tessellatedTorus(int rings, int segments, double major, double minor) {
    TriangleMesh mesh;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const double u = 2 * std::numbers::pi * i / rings, v = 2 * std::numbers::pi * j / segments;
            const double r = major + minor * std::cos(v);
            mesh.positions.insert(mesh.positions.end(),
                                  {float(r * std::cos(u)), float(minor * std::sin(v)), float(r * std::sin(u))});
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const uint32_t a = i * segments + j, b = ((i + 1) % rings) * segments + j;
            const uint32_t c = ((i + 1) % rings) * segments + (j + 1) % segments, d = i * segments + (j + 1) % segments;
            mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
        }
    return mesh;
}

}  // namespace isotrace::bench
