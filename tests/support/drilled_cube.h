// Oriented points on a machined part with sharp edges and known truth: the
// cube [-1, 1]^3 with a cylindrical hole of radius 0.5 along z, sampled
// uniformly by area (exact normals; optional noise along the normals).
#pragma once

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/pointsets/mpu_field.h"

namespace isotrace::testing {

using geometry::MpuPoint;
using geometry::Vec3;

inline constexpr double kHoleRadius = 0.5;
/// `noise`: standard deviation of an offset along each normal.
inline std::vector<MpuPoint> sampleDrilledCube(size_t count, uint32_t seed, double noise = 0.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), angle(0.0, 2.0 * std::numbers::pi);
    const double pi = std::numbers::pi;
    const double sideArea = 4.0, capArea = 4.0 - pi * kHoleRadius * kHoleRadius, wallArea = 2.0 * pi * kHoleRadius * 2.0;
    const double total = 4 * sideArea + 2 * capArea + wallArea;
    std::vector<MpuPoint> points;
    std::uniform_real_distribution<double> pick(0.0, total);
    while (points.size() < count) {
        double a = pick(rng);
        if (a < 4 * sideArea) {  // x = +-1 or y = +-1
            const int face = int(a / sideArea);
            const double s = u(rng), t = u(rng), sign = face % 2 ? 1.0 : -1.0;
            if (face < 2) points.push_back({Vec3(sign, s, t), Vec3(sign, 0, 0)});
            else points.push_back({Vec3(s, sign, t), Vec3(0, sign, 0)});
            continue;
        }
        a -= 4 * sideArea;
        if (a < 2 * capArea) {  // z = +-1 outside the hole
            const double s = u(rng), t = u(rng), sign = a < capArea ? -1.0 : 1.0;
            if (s * s + t * t < kHoleRadius * kHoleRadius) continue;
            points.push_back({Vec3(s, t, sign), Vec3(0, 0, sign)});
            continue;
        }
        const double phi = angle(rng), z = u(rng);  // the hole's wall, normals toward the axis
        points.push_back({Vec3(kHoleRadius * std::cos(phi), kHoleRadius * std::sin(phi), z),
                          Vec3(-std::cos(phi), -std::sin(phi), 0)});
    }
    if (noise > 0) {
        std::normal_distribution<double> offset(0.0, noise);
        for (MpuPoint& p : points) p.position += offset(rng) * p.normal;
    }
    return points;
}

/// Signed distance to the part (negative inside): the larger of the cube's
/// and the hole's, exact near the faces and a lower bound elsewhere.
inline double drilledCubeDistance(const Vec3& p) {
    const Vec3 q = p.cwiseAbs() - Vec3::Ones();
    const double box = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    const double hole = kHoleRadius - std::hypot(p.x(), p.y());  // outside the hole is negative
    return std::max(box, hole);
}

}  // namespace isotrace::testing
