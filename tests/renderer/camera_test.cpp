// The pinhole camera against its definition: the film's edges lie at the
// field of view's half-angle (vertically; the aspect ratio times it
// horizontally), its centre on the line of sight, every direction of unit
// length; and a thin lens's rays meet on the focal plane.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "renderer/camera.h"

using namespace isotrace;

namespace {

// Tangents of the ray's angles from the line of sight, along the
// camera's right and up.
Eigen::Vector2d tangents(const CameraSettings& s, const Vec3& direction) {
    const Vec3 forward = (s.to - s.from).normalized(), right = forward.cross(s.up).normalized();
    const Vec3 up = right.cross(forward);
    const double along = direction.dot(forward);
    return {direction.dot(right) / along, direction.dot(up) / along};
}

}  // namespace

TEST(PerspectiveCamera, FilmEdgesLieAtTheFieldOfView) {
    CameraSettings s;
    s.from = Vec3(1, 2, 3);
    s.to = Vec3(-0.5, 0.2, -1);
    s.verticalFovDegrees = 50;
    const int width = 640, height = 360;
    const PerspectiveCamera camera(s, width, height);
    const double t = std::tan(0.5 * s.verticalFovDegrees * std::numbers::pi / 180.0), a = double(width) / height;
    struct Case {
        double x, y, right, up;
    };
    for (const Case& c : {Case{0, 0, -a * t, t}, Case{width, height, a * t, -t}, Case{width, 0, a * t, t},
                          Case{0.5 * width, 0.5 * height, 0, 0}, Case{0.25 * width, 0.75 * height, -0.5 * a * t, -0.5 * t}}) {
        const Ray r = camera.generateRay(c.x, c.y, {0.3, 0.7});
        EXPECT_NEAR(r.direction.norm(), 1.0, 1e-15);
        EXPECT_EQ(r.origin, s.from);
        const Eigen::Vector2d tan = tangents(s, r.direction);
        EXPECT_NEAR(tan.x(), c.right, 1e-14) << c.x << ", " << c.y;
        EXPECT_NEAR(tan.y(), c.up, 1e-14) << c.x << ", " << c.y;
    }
}

TEST(PerspectiveCamera, ThinLensRaysMeetOnTheFocalPlane) {
    CameraSettings s;
    s.aperture = 0.2;
    s.focusDistance = 4;
    const PerspectiveCamera camera(s, 320, 240);
    const Vec3 forward = (s.to - s.from).normalized();
    const Ray pinhole = [&] {
        CameraSettings p = s;
        p.aperture = 0;
        return PerspectiveCamera(p, 320, 240).generateRay(100.5, 60.25, {0, 0});
    }();
    // Where the pinhole ray crosses the focal plane, every lens sample's ray does too.
    const Vec3 focus = s.from + (s.focusDistance / pinhole.direction.dot(forward)) * pinhole.direction;
    for (const Eigen::Vector2d& lens : {Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(0.9, 0.6), Eigen::Vector2d(0.5, 0.99)}) {
        const Ray r = camera.generateRay(100.5, 60.25, lens);
        EXPECT_NEAR(r.direction.norm(), 1.0, 1e-15);
        EXPECT_LE((r.origin - s.from).norm(), 0.5 * s.aperture + 1e-15);
        EXPECT_GT((r.origin - s.from).norm(), 0.0);
        const double t = (focus - r.origin).dot(forward) / r.direction.dot(forward);
        EXPECT_LT((r.origin + t * r.direction - focus).norm(), 1e-12);
    }
}
