// Convolution surfaces along segment skeletons with the Cauchy kernel
// h(r) = 1 / (1 + (r/R)^2)^2 (McCormack and Sherstyuk), whose integral
// along a segment has a closed form. Each segment's integral is normalised by
// 2 / (pi R) so that an infinite line scores 1 on its axis:
//   f(p) = T - sum_i w_i F_i(p).
// The gradient is exact (automatic differentiation of the closed form).
#pragma once

#include <vector>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct ConvolutionSegment {
    Vec3 a = Vec3::Zero();
    Vec3 b = Vec3(1, 0, 0);
    double radius = 0.5;  ///< R of the kernel
    double weight = 1.0;
};

struct ConvolutionField {
    double threshold = 0.5;
    std::vector<ConvolutionSegment> segments;

    double value(const Vec3& p) const;
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    Interval range(const Box3& box) const;
    double lipschitz(const Box3& box) const;
    Box3 bounds() const;
    size_t termCount() const { return segments.size(); }
};

}  // namespace isotrace::geometry
