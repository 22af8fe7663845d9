// A surface traced through its cell accelerators (local models, exact
// polynomial roots) against the same field marched by the general sphere
// tracer: both must agree on every ray, primary and leaving the surface as
// bounces and shadow rays do, on hit or miss, distance and normal, and
// occlusion queries (which may stop at any proven root) on hit or miss.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "geometry/tracing/implicit_surface.h"
#include "support/embree_scene.h"
#include "support/random_rays.h"

namespace isotrace::testing {

/// Options whose only accelerator is `Accelerator`: it takes every cell it
/// can, and the general tracer marches the rest.
template <class Accelerator>
geometry::ImplicitSurfaceOptions onlyAccelerator() {
    geometry::ImplicitSurfaceOptions options;
    options.cellAccelerators = {std::make_shared<Accelerator>()};
    return options;
}

/// A surface traced with the accelerators of `fastOptions` and the same
/// surface marched by the general tracer alone, each in its Embree scene.
struct FastAndExact {
    static geometry::ImplicitSurfaceOptions marchingOnly() {
        geometry::ImplicitSurfaceOptions options;
        options.cellAccelerators.clear();
        return options;
    }
    FastAndExact(const geometry::FieldProgram& program, const geometry::ImplicitSurfaceOptions& fastOptions)
        : fast(program, fastOptions), exact(program, marchingOnly()) {
        fastScene.attach(fast);
        exactScene.attach(exact);
        fastScene.commit();
        exactScene.commit();
    }
    geometry::ImplicitSurface fast, exact;
    EmbreeScene fastScene, exactScene;
};

/// `fastOptions` chooses the accelerators under test (all by default).
inline void expectSameHitsAsMarching(const geometry::FieldProgram& program, int rays, int minimumHits,
                                     int minimumSecondaryHits, double minimumNormalCosine = 0.999,
                                     const geometry::ImplicitSurfaceOptions& fastOptions = {}) {
    using geometry::Vec3;
    FastAndExact scenes(program, fastOptions);
    const geometry::ImplicitSurface &fast = scenes.fast, &exact = scenes.exact;
    const EmbreeScene &fastScene = scenes.fastScene, &exactScene = scenes.exactScene;
    ASSERT_GT(fast.acceleratedCellCount(), 0u);
    ASSERT_EQ(exact.acceleratedCellCount(), 0u);
    const double size = fast.bounds().extent().norm();
    std::mt19937 rng(11);
    std::normal_distribution<double> n;
    int hits = 0, secondaryHits = 0;
    for (int i = 0; i < rays; ++i) {
        const auto ray = randomRayAt(fast.bounds(), rng);
        const auto a = fastScene.intersect(ray.origin, ray.direction), b = exactScene.intersect(ray.origin, ray.direction);
        ASSERT_EQ(a.hit, b.hit) << "ray " << i;
        // Occlusion queries may settle on any proven root (TraceSettings::anyHit).
        ASSERT_EQ(fastScene.occluded(ray.origin, ray.direction, 1e30), b.hit) << "ray " << i;
        if (!a.hit) continue;
        ++hits;
        ASSERT_NEAR(a.t, b.t, 1e-5 * size) << "ray " << i;
        // ... and only within the segment asked about.
        ASSERT_FALSE(fastScene.occluded(ray.origin, ray.direction, b.t - 1e-4 * size)) << "ray " << i;
        ASSERT_TRUE(fastScene.occluded(ray.origin, ray.direction, b.t + 1e-4 * size)) << "ray " << i;
        // Normals come from the exact gradient at (or within resolution of)
        // the hit, where the surface has one: at a singular point (Taubin's
        // heart is singular along its equator, where its cube has a triple
        // root: |grad f| ~ 1e-9 there) the gradient's direction is rounding.
        if (b.normal.norm() > 1e-6 * exact.globalLipschitz()) {
            EXPECT_GT(a.normal.normalized().dot(b.normal.normalized()), minimumNormalCosine) << "ray " << i;
        }
        // A ray leaving the surface into the outer hemisphere.
        const Vec3 p = ray.origin + double(a.t) * ray.direction, normal = b.normal.normalized();
        Vec3 d = Vec3(n(rng), n(rng), n(rng)).normalized();
        if (d.dot(normal) < 0) d = -d;
        const Vec3 o = (p + 1e-4 * size * normal).cast<float>().cast<double>();
        d = d.cast<float>().cast<double>();
        const auto c = fastScene.intersect(o, d), e = exactScene.intersect(o, d);
        ASSERT_EQ(c.hit, e.hit) << "secondary ray " << i;
        EXPECT_EQ(fastScene.occluded(o, d, 1e30), exactScene.occluded(o, d, 1e30)) << "secondary ray " << i;
        if (c.hit) {
            ++secondaryHits;
            ASSERT_NEAR(c.t, e.t, 1e-5 * size) << "secondary ray " << i;
        }
    }
    EXPECT_GE(hits, minimumHits);
    EXPECT_GE(secondaryHits, minimumSecondaryHits);
}

/// Field terms summed per ray (the trace counters' evaluations: exact terms
/// and model monomials alike) over `rays` random rays through the bounds.
inline double evaluationsPerRay(const geometry::ImplicitSurface& surface, int rays = 200) {
    geometry::TraceCounters& counters = geometry::threadTraceCounters();
    std::mt19937 rng(5);
    const uint64_t before = counters.evaluations;
    for (int i = 0; i < rays; ++i) {
        const auto ray = randomRayAt(surface.bounds(), rng);
        surface.intersect(ray.origin, ray.direction, 0.0, 1e30);
    }
    return double(counters.evaluations - before) / double(rays);
}

/// The same on rays that graze the surface: from hits of random rays, rays
/// along a tangent, shifted off the surface to either side by 1e-5 to 1e-2
/// of the bounds' diagonal and tilted a little. Inside, they meet the
/// surface twice close together; outside, they pass within a hair of it.
/// This is where a tracer's proofs are tested hardest: a bound too small
/// that calls a span monotone, or a sign proven, when it is not.
inline void expectSameHitsOnGrazingRays(const geometry::FieldProgram& program, int rays, int minimumHits,
                                        const geometry::ImplicitSurfaceOptions& fastOptions = {}) {
    using geometry::Vec3;
    FastAndExact scenes(program, fastOptions);
    const geometry::ImplicitSurface &fast = scenes.fast, &exact = scenes.exact;
    const EmbreeScene &fastScene = scenes.fastScene, &exactScene = scenes.exactScene;
    ASSERT_GT(fast.acceleratedCellCount(), 0u);
    const double size = fast.bounds().extent().norm();
    std::mt19937 rng(17);
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int tried = 0, hits = 0;
    for (int i = 0; tried < rays && i < 20 * rays; ++i) {
        const auto ray = randomRayAt(exact.bounds(), rng);
        const auto a = exactScene.intersect(ray.origin, ray.direction);
        if (!a.hit) continue;
        const Vec3 p = ray.origin + double(a.t) * ray.direction, normal = a.normal.normalized();
        Vec3 tangent = Vec3(n(rng), n(rng), n(rng)).cross(normal).normalized();
        const double side = (i % 2 ? 1.0 : -1.0) * size * std::pow(10.0, -5.0 + 3.0 * u(rng));
        const Vec3 d = (tangent + 0.02 * n(rng) * normal).normalized().cast<float>().cast<double>();
        const Vec3 o = (p + side * normal - 0.05 * size * d).cast<float>().cast<double>();
        ++tried;
        const auto c = fastScene.intersect(o, d), e = exactScene.intersect(o, d);
        ASSERT_EQ(c.hit, e.hit) << "grazing ray " << tried << " at " << side / size << " of the diagonal";
        ASSERT_EQ(fastScene.occluded(o, d, 1e30), e.hit) << "grazing ray " << tried << " (occlusion)";
        if (!c.hit) continue;
        ++hits;
        ASSERT_NEAR(c.t, e.t, 1e-5 * size) << "grazing ray " << tried;
    }
    EXPECT_EQ(tried, rays);
    EXPECT_GE(hits, minimumHits);
}

}  // namespace isotrace::testing
