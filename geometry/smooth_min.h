// The quadratic polynomial smooth minimum with blend radius k > 0 (Quilez),
// shared by the smooth_union operator and smooth sphere sets. Its partial
// derivatives are h and 1 - h (both in [0, 1]), so it is monotone in each
// operand and its gradient is a convex combination of the operands'; once
// b - a >= k, h is exactly 1 and the result exactly a.
#pragma once

#include <algorithm>

namespace isotrace::geometry {

struct SmoothMinResult {
    double value;
    double h;  ///< weight of operand a
};

inline SmoothMinResult smoothMin(double a, double b, double k) {
    const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
    return {b * (1.0 - h) + a * h - k * h * (1.0 - h), h};
}

}  // namespace isotrace::geometry
