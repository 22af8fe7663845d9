// Points stored axis by axis give back the points they were given, in
// order, and each axis's coordinates as one contiguous array.
#include <gtest/gtest.h>

#include "geometry/points_by_axis.h"

using namespace isotrace::geometry;

TEST(PointsByAxis, KeepsPointsInOrderWithEachAxisContiguous) {
    const std::vector<Vec3> given = {Vec3(1, 2, 3), Vec3(-4, 5, -6), Vec3(0.5, 0.25, 0.125)};
    PointsByAxis points = given;
    points.push_back(Vec3(7, 8, 9));
    ASSERT_EQ(points.size(), 4u);
    for (size_t i = 0; i < given.size(); ++i) {
        EXPECT_EQ(points[i], given[i]);
        EXPECT_EQ(points.x()[i], given[i].x());
        EXPECT_EQ(points.y()[i], given[i].y());
        EXPECT_EQ(points.z()[i], given[i].z());
    }
    EXPECT_EQ(points[3], Vec3(7, 8, 9));
    size_t n = 0;
    for (const Vec3& p : points) EXPECT_EQ(p, points[n++]);
    EXPECT_EQ(n, 4u);
    points = std::vector<Vec3>{Vec3(1, 1, 1)};
    EXPECT_EQ(points.size(), 1u);
    EXPECT_EQ(points[0], Vec3(1, 1, 1));
    points.clear();
    EXPECT_TRUE(points.empty());
}
