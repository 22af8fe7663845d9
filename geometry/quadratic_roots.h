// The real roots of a t^2 + 2 b t + c (a > 0), in the form that does not
// cancel (q / a and c / q with q = -(b + sign(b) sqrt(b^2 - a c))): rays
// meet spheres, cylinders and balls through it.
#pragma once

#include <cmath>
#include <utility>

namespace isotrace::geometry {

/// False when there is no real root; else `near` <= `far`.
inline bool quadraticRoots(double a, double b, double c, double& near, double& far) {
    const double discriminant = b * b - a * c;
    if (!(discriminant >= 0.0)) return false;
    const double q = -(b + std::copysign(std::sqrt(discriminant), b));
    near = q / a;
    far = q != 0.0 ? c / q : near;
    if (near > far) std::swap(near, far);
    return true;
}

}  // namespace isotrace::geometry
