// Points stored axis by axis: every x, then every y, then every z. Sums over
// thousands of points (a variational field's exact value, its local models)
// then load whole vector registers of one coordinate instead of gathering
// them from interleaved triples (bench/variational_render).
#pragma once

#include <cstddef>
#include <iterator>
#include <vector>

#include "geometry/vector_types.h"

namespace isotrace::geometry {

class PointsByAxis {
public:
    PointsByAxis() = default;
    PointsByAxis(const std::vector<Vec3>& points) { assign(points); }  // NOLINT: a list of points is one
    PointsByAxis& operator=(const std::vector<Vec3>& points) {
        assign(points);
        return *this;
    }

    size_t size() const { return x_.size(); }
    bool empty() const { return x_.empty(); }
    Vec3 operator[](size_t i) const { return Vec3(x_[i], y_[i], z_[i]); }
    void reserve(size_t n) {
        x_.reserve(n);
        y_.reserve(n);
        z_.reserve(n);
    }
    void push_back(const Vec3& p) {
        x_.push_back(p.x());
        y_.push_back(p.y());
        z_.push_back(p.z());
    }
    void clear() {
        x_.clear();
        y_.clear();
        z_.clear();
    }
    /// The coordinates along one axis, size() of them.
    const double* x() const { return x_.data(); }
    const double* y() const { return y_.data(); }
    const double* z() const { return z_.data(); }

    /// Iterates points by value (there is no Vec3 in memory to refer to,
    /// so it is an input iterator only).
    class const_iterator {
    public:
        using iterator_category = std::input_iterator_tag;
        using value_type = Vec3;
        using difference_type = std::ptrdiff_t;
        using pointer = void;
        using reference = Vec3;
        const_iterator() = default;
        const_iterator(const PointsByAxis* points, size_t i) : points_(points), i_(i) {}
        Vec3 operator*() const { return (*points_)[i_]; }
        const_iterator& operator++() {
            ++i_;
            return *this;
        }
        const_iterator operator++(int) {
            const_iterator before = *this;
            ++i_;
            return before;
        }
        bool operator==(const const_iterator& o) const { return i_ == o.i_; }

    private:
        const PointsByAxis* points_ = nullptr;
        size_t i_ = 0;
    };
    const_iterator begin() const { return {this, 0}; }
    const_iterator end() const { return {this, size()}; }

private:
    void assign(const std::vector<Vec3>& points) {
        clear();
        reserve(points.size());
        for (const Vec3& p : points) push_back(p);
    }

    std::vector<double> x_, y_, z_;
};

}  // namespace isotrace::geometry
