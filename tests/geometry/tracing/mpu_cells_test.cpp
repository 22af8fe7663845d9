// MPU surfaces traced through their parts (polynomial roots inside bands)
// and by the general sphere tracer (per-point safe distances) must agree on
// every ray, primary and leaving the surface, for a scan and for a part
// with sharp edges.
#include <gtest/gtest.h>

#include <random>

#include "geometry/pointsets/mpu_field.h"
#include "geometry/tracing/implicit_surface.h"
#include "geometry/variational/constraints.h"
#include "support/drilled_cube.h"
#include "support/embree_scene.h"
#include "support/random_rays.h"

using namespace isotrace::geometry;

namespace {

void expectSameHits(const MpuField& field, int rays) {
    FieldProgram program;
    program.addLeaf(MpuLeafField{std::make_shared<const MpuField>(field)});
    ImplicitSurfaceOptions exactOptions;
    exactOptions.cellAccelerators.clear();
    ImplicitSurface fast(program), exact(program, exactOptions);
    ASSERT_GT(fast.acceleratedCellCount(), 0u);
    ASSERT_EQ(exact.acceleratedCellCount(), 0u);
    isotrace::testing::EmbreeScene fastScene, exactScene;
    fastScene.attach(fast);
    exactScene.attach(exact);
    fastScene.commit();
    exactScene.commit();
    const double size = fast.bounds().extent().norm();
    std::mt19937 rng(11);
    std::normal_distribution<double> n;
    int hits = 0, secondaryHits = 0;
    for (int i = 0; i < rays; ++i) {
        const auto ray = isotrace::testing::randomRayAt(fast.bounds(), rng);
        const auto a = fastScene.intersect(ray.origin, ray.direction), b = exactScene.intersect(ray.origin, ray.direction);
        ASSERT_EQ(a.hit, b.hit) << "ray " << i;
        if (!a.hit) continue;
        ++hits;
        ASSERT_NEAR(a.t, b.t, 1e-5 * size) << "ray " << i;
        EXPECT_GT(a.normal.normalized().dot(b.normal.normalized()), 0.999) << "ray " << i;
        // A ray leaving the surface into the outer hemisphere, as bounces do.
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
    EXPECT_GT(hits, rays / 10);
    EXPECT_GT(secondaryHits, 10);
}

}  // namespace

TEST(MpuCells, AgreeWithMarchingOnAScan) {
    std::vector<MpuPoint> points;
    for (const OrientedPoint& p : readOrientedPoints(std::string(ISOTRACE_SOURCE_DIR) + "/scenes/scans/kitten.xyz"))
        points.push_back({p.position, p.normal});
    expectSameHits(MpuField::fit(points), 600);
}

TEST(MpuCells, AgreeWithMarchingAcrossSharpEdges) {
    expectSameHits(MpuField::fit(isotrace::testing::sampleDrilledCube(20000, 9)), 1500);
}
