#include "geometry/meshing/mesh_analysis.h"

#include <gtest/gtest.h>

#include <cmath>

#include "support/compile_field.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

namespace {

// `equilateral` unit equilateral triangles and `slivers` triangles of
// height 1e-3 on a base of 1, side by side.
IndexedMesh strip(int equilateral, int slivers) {
    IndexedMesh m;
    auto add = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        const auto first = uint32_t(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {a, b, c});
        m.triangles.push_back({first, first + 1, first + 2});
    };
    for (int i = 0; i < equilateral; ++i) add(Vec3(2.0 * i, 0, 0), Vec3(2.0 * i + 1, 0, 0), Vec3(2.0 * i + 0.5, std::sqrt(0.75), 0));
    for (int i = 0; i < slivers; ++i) add(Vec3(2.0 * i, 5, 0), Vec3(2.0 * i + 1, 5, 0), Vec3(2.0 * i + 0.5, 5.001, 0));
    return m;
}

}  // namespace

// Aspect ratio: longest edge over shortest altitude times sqrt(3)/2, so 1
// for equilateral; a sliver of height h on a unit base has 1/h sqrt(3)/2.
// The 99th percentile ignores one sliver in 101 triangles, not two.
TEST(MeshAnalysis, AspectRatiosWorstAndNinetyNinthPercentile) {
    const FieldProgram field = compileField(R"({"type": "sphere", "radius": 1})");
    const double sliver = 1e3 * std::sqrt(3.0) / 2.0;

    const MeshAccuracy one = measureAccuracy(strip(100, 1), field);
    EXPECT_NEAR(one.worstAspectRatio, sliver, 1e-6 * sliver);
    EXPECT_NEAR(one.aspectRatio99thPercentile, 1.0, 1e-12);

    const MeshAccuracy two = measureAccuracy(strip(99, 2), field);
    EXPECT_NEAR(two.aspectRatio99thPercentile, sliver, 1e-6 * sliver);

    const MeshAccuracy none = measureAccuracy(strip(10, 0), field);
    EXPECT_NEAR(none.worstAspectRatio, 1.0, 1e-12);
    EXPECT_NEAR(none.aspectRatio99thPercentile, 1.0, 1e-12);
}
