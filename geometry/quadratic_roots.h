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

/// The roots of a t^2 + b t + c strictly inside (lo, hi), ascending,
/// appended to out[count...] (room for two).
inline void quadraticRootsBetween(double a, double b, double c, double lo, double hi, double* out, int& count) {
    if (a == 0.0) {
        if (b != 0.0) {
            const double t = -c / b;
            if (t > lo && t < hi) out[count++] = t;
        }
        return;
    }
    const double discriminant = b * b - 4.0 * a * c;
    if (discriminant < 0.0) return;
    const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
    double r[2] = {q / a, q != 0.0 ? c / q : q / a};
    if (r[0] > r[1]) std::swap(r[0], r[1]);
    for (const double t : r)
        if (t > lo && t < hi) out[count++] = t;
}

}  // namespace isotrace::geometry
