// The octahedron against its geometry: zero on its vertices and faces, the
// exact distance over a face and inside, and never more than the distance
// (to the nearest vertex, for points beyond one).
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/fields/octahedron.h"

using namespace isotrace::geometry;

TEST(Octahedron, VanishesOnItsSurfaceAndMeasuresDistanceOverFacesAndInside) {
    const OctahedronField f{Vec3(0.5, -0.2, 0.1), 2.0};
    for (const Vec3& axis : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)})
        EXPECT_NEAR(f.value(f.center + 2.0 * axis), 0.0, 1e-15) << "a vertex";
    const Vec3 onFace = f.center + Vec3(2.0, 2.0, 2.0) / 3.0;  // the face x + y + z = 2's centre
    EXPECT_NEAR(f.value(onFace), 0.0, 1e-15);
    const Vec3 normal = Vec3(1, 1, 1).normalized();
    EXPECT_NEAR(f.value(onFace + 0.3 * normal), 0.3, 1e-14) << "above the face: the distance";
    EXPECT_NEAR(f.value(f.center), -2.0 / std::sqrt(3.0), 1e-15) << "the centre: the inradius";
    Vec3 gradient;
    f.valueAndGradient(onFace + 0.3 * normal, gradient);
    EXPECT_NEAR((gradient - normal).norm(), 0.0, 1e-15);
    // Beyond a vertex the nearest point is the vertex, and the value is below it.
    const Vec3 vertex = f.center + Vec3(2.0, 0, 0);
    for (const Vec3& away : {Vec3(1, 0, 0), Vec3(1, 0.2, -0.1), Vec3(0.7, 0.7, 0)}) {
        const Vec3 p = vertex + 0.5 * away.normalized();
        EXPECT_LE(f.value(p), (p - vertex).norm() + 1e-15);
        EXPECT_GT(f.value(p), 0.0);
    }
}
