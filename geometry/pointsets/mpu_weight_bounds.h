// Bounds of MPU's weight w = (1 - r^2 / R^2)^3 and its derivatives over a
// range of distances, and the range of a quadric over a box: written once
// for doubles and for vector lanes (geometry/lanes.h), so that the numerator
// models bound a box's locals with the same arithmetic in their vector
// kernels (mpu_model_kernels.cpp) as one by one. Always inlined: the
// kernels compiled for wider vectors must not define them for others.
#pragma once

#include <cmath>

#include "geometry/lanes.h"

namespace isotrace::geometry {

// The upper triangle of a symmetric matrix.
template <class T>
struct Symmetric3 {
    T xx, xy, xz, yy, yz, zz;
};

/// The largest |d/dr (1 - r^2/R^2)^3| R: 6 t (1 - t^2)^2 at t = 1/sqrt 5.
constexpr double kMpuWeightSlope = 1.7173285067805897;

/// The largest |grad w| of a ball of radius R over distances in `distance`
/// from its centre: 6 r (1 - r^2/R^2)^2 / R^2 rises up to r = R / sqrt 5 and
/// falls after.
template <class T>
[[gnu::always_inline]] inline T mpuWeightSlope(const T& distanceLo, const T& distanceHi, const T& R) {
    const T peak = R / std::sqrt(5.0);
    const T a = distanceLo, b = lesser(distanceHi, R);
    auto slope = [&R](const T& r) {
        const T s = 1.0 - r * r / (R * R);
        return T(6.0 * r * s * s / (R * R));
    };
    const T within = select(b <= peak, slope(b), select(a >= peak, slope(a), T(kMpuWeightSlope / R)));
    return select(a >= R, T(0.0), within);
}

// The largest |d^2/dtau^2 w(x + tau u)| over unit u and distances r from
// the ball's centre in `distance`. With v = r^2 / R^2 and sigma = 1 - v,
// w'' = 6 sigma s'^2 - 3 sigma^2 s'' where 0 <= s'^2 <= 4 v / R^2 and
// s'' = 2 / R^2, so w'' lies in [-6 sigma^2, 6 sigma (5 v - 1)] / R^2: the
// first magnitude falls with v, the second peaks at v = 0.6 (4.8 / R^2).
// Summing the two terms' largest magnitudes instead would give 30 / R^2.
template <class T>
[[gnu::always_inline]] inline T weightCurvatureBound(const T& distanceLo, const T& distanceHi, const T& R) {
    const T R2 = R * R;
    const T lo = lesser(T(distanceLo * distanceLo / R2), T(1.0)), hi = lesser(T(distanceHi * distanceHi / R2), T(1.0));
    auto rising = [](const T& v) { return T(6.0 * (1.0 - v) * (5.0 * v - 1.0)); };
    const T peak = select(hi <= 0.6, rising(hi), select(lo >= 0.6, rising(lo), T(4.8)));
    return greater(T(6.0 * (1.0 - lo) * (1.0 - lo)), peak) / R2 * (1 + 1e-12);
}

// The same for |w'''|: w''' = s' (36 sigma / R^2 - 6 s'^2) with
// 0 <= |s'| <= P = 2 x / R, x = r / R. Over s' in [0, P] its magnitude is
// largest at s' = sqrt(2 sigma) / R (24 sqrt 2 sigma^1.5 / R^3, falling with
// x) or at s' = P (|72 x - 120 x^3| / R^3, extreme at x^2 = 0.2 and at the
// interval's ends).
template <class T>
[[gnu::always_inline]] inline T weightThirdBound(const T& distanceLo, const T& distanceHi, const T& R) {
    using std::abs, std::sqrt;
    const T lo = lesser(T(distanceLo / R), T(1.0)), hi = lesser(T(distanceHi / R), T(1.0));
    const T sigma = 1.0 - lo * lo;
    auto atEnd = [](const T& x) { return T(abs(T(72.0 * x - 120.0 * x * x * x))); };
    const double critical = std::sqrt(0.2);
    const T ends = greater(greater(T(24.0 * std::sqrt(2.0) * sigma * sqrt(sigma)), atEnd(lo)), atEnd(hi));
    const T bound = select(lo < critical, select(critical < hi, greater(ends, atEnd(T(critical))), ends), ends);
    return bound / (R * R * R) * (1 + 1e-12);
}

// The same for |w''''|, where the ball holds the whole box (w is smooth
// there): w'''' = -36 s'^2 s'' + 18 sigma s''^2, two terms of opposite
// signs, the first at most 288 x^2 / R^4, the second 72 sigma / R^4.
template <class T>
[[gnu::always_inline]] inline T weightFourthBound(const T& distanceLo, const T& distanceHi, const T& R) {
    const T lo = lesser(T(distanceLo / R), T(1.0)), hi = lesser(T(distanceHi / R), T(1.0));
    const T R2 = R * R;
    return greater(T(288.0 * hi * hi), T(72.0 * (1.0 - lo * lo))) / (R2 * R2) * (1 + 1e-12);
}

// The range of c + g . y + y^T A y over |y_k| <= h_k (quadraticRange in
// mpu_numerator_model.h), for doubles and lanes alike.
template <class T>
struct RangeOf {
    T lo, hi;
    [[gnu::always_inline]] T magnitude() const {
        using std::abs;
        return greater(T(abs(lo)), T(abs(hi)));
    }
};
template <class T>
[[gnu::always_inline]] inline RangeOf<T> quadraticRangeOf(const T& value, const T& gx, const T& gy, const T& gz,
                                                         const Symmetric3<T>& a, const T& hx, const T& hy,
                                                         const T& hz) {
    using std::abs;
    const T linear = abs(gx) * hx + abs(gy) * hy + abs(gz) * hz;
    const T dx = a.xx * hx * hx, dy = a.yy * hy * hy, dz = a.zz * hz * hz;
    const T cross = 2.0 * (abs(a.xy) * hx * hy + abs(a.xz) * hx * hz + abs(a.yz) * hy * hz);
    const T zero(0.0);
    const T lo = value - linear + (lesser(dx, zero) + lesser(dy, zero) + lesser(dz, zero)) - cross;
    const T hi = value + linear + (greater(dx, zero) + greater(dy, zero) + greater(dz, zero)) + cross;
    return {lo, hi};
}

}  // namespace isotrace::geometry
