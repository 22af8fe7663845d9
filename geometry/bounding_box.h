// Axis-aligned boxes: the domain of every range and Lipschitz query.
#pragma once

#include <algorithm>
#include <limits>
#include <ostream>

#include "geometry/interval.h"
#include "geometry/vector_types.h"

namespace isotrace::geometry {

struct Box3 {
    Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 upper = Vec3::Constant(-std::numeric_limits<double>::infinity());

    Box3() = default;
    Box3(const Vec3& lo, const Vec3& hi) : lower(lo), upper(hi) {}

    static Box3 everything() {
        constexpr double inf = std::numeric_limits<double>::infinity();
        return {Vec3::Constant(-inf), Vec3::Constant(inf)};
    }
    static Box3 around(const Vec3& center, double radius) {
        return {center - Vec3::Constant(radius), center + Vec3::Constant(radius)};
    }

    bool isEmpty() const { return (lower.array() > upper.array()).any(); }
    bool isFinite() const { return lower.allFinite() && upper.allFinite(); }
    Vec3 center() const { return 0.5 * (lower + upper); }
    Vec3 extent() const { return upper - lower; }
    double halfDiagonal() const { return 0.5 * extent().norm(); }
    Interval axis(int i) const { return {lower[i], upper[i]}; }

    bool contains(const Vec3& p) const {
        return (p.array() >= lower.array()).all() && (p.array() <= upper.array()).all();
    }
    bool contains(const Box3& b) const { return contains(b.lower) && contains(b.upper); }
    void extend(const Vec3& p) {
        lower = lower.cwiseMin(p);
        upper = upper.cwiseMax(p);
    }
    void extend(const Box3& b) {
        lower = lower.cwiseMin(b.lower);
        upper = upper.cwiseMax(b.upper);
    }
    Box3 expanded(double margin) const {
        if (isEmpty()) return *this;
        return {lower - Vec3::Constant(margin), upper + Vec3::Constant(margin)};
    }
    Vec3 corner(int i) const {
        return {(i & 1) ? upper.x() : lower.x(), (i & 2) ? upper.y() : lower.y(), (i & 4) ? upper.z() : lower.z()};
    }
    /// The eighth of the box between corner i and the centre (octree children).
    Box3 octant(int i) const {
        const Vec3 c = center(), k = corner(i);
        return {k.cwiseMin(c), k.cwiseMax(c)};
    }

    /// Smallest and largest distance from p to a point of the box.
    Interval distanceRange(const Vec3& p) const {
        const Vec3 nearest = p.cwiseMax(lower).cwiseMin(upper);
        const Vec3 farthest = (p - lower).cwiseAbs().cwiseMax((p - upper).cwiseAbs());
        return {(p - nearest).norm(), farthest.norm()};
    }
};

inline Box3 intersection(const Box3& a, const Box3& b) {
    return {a.lower.cwiseMax(b.lower), a.upper.cwiseMin(b.upper)};
}
inline Box3 unionOf(const Box3& a, const Box3& b) {
    Box3 r = a;
    r.extend(b);
    return r;
}

/// Bounding box of the image of `box` under x -> linear * x + offset.
inline Box3 transformBox(const Mat3& linear, const Vec3& offset, const Box3& box) {
    if (box.isEmpty()) return box;
    if (!box.isFinite()) return Box3::everything();
    // Interval matrix-vector product: exact bounds of an affine image of a box.
    const Vec3 c = linear * box.center() + offset;
    const Vec3 r = linear.cwiseAbs() * (0.5 * box.extent());
    return {c - r, c + r};
}

inline std::ostream& operator<<(std::ostream& os, const Box3& b) {
    return os << "[(" << b.lower.transpose() << "), (" << b.upper.transpose() << ")]";
}

}  // namespace isotrace::geometry
