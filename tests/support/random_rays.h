// Random rays for intersector tests: from a sphere around a box towards
// random points inside it, rounded to float as Embree will round them, so
// that an Embree-backed intersector and a double-precision reference see
// the same ray.
#pragma once

#include <random>

#include "geometry/bounding_box.h"

namespace isotrace::testing {

struct RandomRay {
    geometry::Vec3 origin, direction;
};

template <class Rng>
RandomRay randomRayAt(const geometry::Box3& bounds, Rng& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> n;
    const double radius = 2.0 * bounds.halfDiagonal();
    const geometry::Vec3 origin =
        bounds.center() + radius * geometry::Vec3(n(rng), n(rng), n(rng)).normalized();
    const geometry::Vec3 target = bounds.lower + geometry::Vec3(u(rng), u(rng), u(rng)).cwiseProduct(bounds.extent());
    return {origin.cast<float>().cast<double>(), (target - origin).normalized().cast<float>().cast<double>()};
}

}  // namespace isotrace::testing
