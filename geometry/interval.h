// Closed intervals [lo, hi] with the arithmetic the field bounds need.
//
// Every operation returns an interval that contains all results of the
// operation on members of its operands. Round-off is absorbed where the
// geometry library publishes a range (FieldProgram widens its results by a few
// ulps), not in each operation, to keep the inner loops short.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

namespace isotrace::geometry {

struct Interval {
    double lo = 0.0;
    double hi = 0.0;

    constexpr Interval() = default;
    constexpr Interval(double v) : lo(v), hi(v) {}
    constexpr Interval(double l, double h) : lo(l), hi(h) {}

    static constexpr Interval everything() {
        return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    }

    constexpr bool contains(double v) const { return lo <= v && v <= hi; }
    constexpr bool containsZero() const { return lo <= 0.0 && 0.0 <= hi; }
    constexpr double width() const { return hi - lo; }
    constexpr double magnitude() const { return std::max(std::abs(lo), std::abs(hi)); }
};

inline Interval operator+(Interval a, Interval b) { return {a.lo + b.lo, a.hi + b.hi}; }
inline Interval operator-(Interval a, Interval b) { return {a.lo - b.hi, a.hi - b.lo}; }
inline Interval operator-(Interval a) { return {-a.hi, -a.lo}; }
inline Interval operator*(Interval a, Interval b) {
    const double p1 = a.lo * b.lo, p2 = a.lo * b.hi, p3 = a.hi * b.lo, p4 = a.hi * b.hi;
    return {std::min({p1, p2, p3, p4}), std::max({p1, p2, p3, p4})};
}
inline Interval operator*(double s, Interval a) {
    return s >= 0 ? Interval{s * a.lo, s * a.hi} : Interval{s * a.hi, s * a.lo};
}
inline Interval& operator+=(Interval& a, Interval b) { return a = a + b; }

inline Interval min(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
inline Interval max(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }

/// x^n for a whole n >= 0; even powers of a straddling interval start at 0.
inline double wholePower(double x, int n) {
    double r = 1.0;
    for (; n > 0; n >>= 1, x *= x)
        if (n & 1) r *= x;
    return r;
}
inline Interval pow(Interval a, int n) {
    if (n == 0) return {1.0, 1.0};
    const double pl = wholePower(a.lo, n), ph = wholePower(a.hi, n);
    if (n % 2 == 1) return {pl, ph};
    if (a.containsZero()) return {0.0, std::max(pl, ph)};
    return {std::min(pl, ph), std::max(pl, ph)};
}

/// Widens an interval by a relative and absolute margin to absorb round-off.
inline Interval widened(Interval a, double relative = 1e-12) {
    const double m = relative * std::max(1.0, a.magnitude());
    return {a.lo - m, a.hi + m};
}

inline std::ostream& operator<<(std::ostream& os, Interval a) { return os << '[' << a.lo << ", " << a.hi << ']'; }

}  // namespace isotrace::geometry
