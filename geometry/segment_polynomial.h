// A function along a ray segment, u in [0, 1], that is a sum of polynomial
// terms each present on an interval of its own (a ball the segment crosses,
// a piece of a max or min): between consecutive interval ends it is one
// polynomial, swept in order, each searched for its first root in the
// Bernstein basis (bernstein_root.h). Field kinds whose terms are
// polynomials along a ray (MPU locals, blobs with polynomial kernels) are
// solved exactly with it, without a Lipschitz bound or a step.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "geometry/bernstein_root.h"

namespace isotrace::geometry {

template <int Degree>
class SegmentPolynomialSum {
public:
    using Polynomial = Monomials<Degree>;

    /// Empties the sum, keeping its storage (one instance per thread serves
    /// every ray without allocating).
    void clear() {
        base_ = {};
        terms_.clear();
        changes_.clear();
    }
    void addConstant(double c) { base_[0] += c; }
    /// `p` on [from, to], clamped to [0, 1]; nothing when that is empty.
    void add(const Polynomial& p, double from, double to) {
        from = std::max(from, 0.0);
        to = std::min(to, 1.0);
        if (!(from < to)) return;
        if (from <= 0.0 && to >= 1.0) {
            for (int k = 0; k <= Degree; ++k) base_[k] += p[k];
            return;
        }
        const auto index = uint32_t(terms_.size());
        terms_.push_back(p);
        if (from <= 0.0) {
            for (int k = 0; k <= Degree; ++k) base_[k] += p[k];
        } else {
            changes_.push_back({from, index, +1.0});
        }
        if (to < 1.0) changes_.push_back({to, index, -1.0});
    }

    struct Root {
        bool found = false;
        double u = 0.0;
        int pieces = 0;  ///< polynomial pieces searched, halvings and refinement steps included
    };

    /// The first u where the sum changes sign (or is zero), to within
    /// `tolerance`; not found when every piece is proven free of roots.
    Root firstRoot(double tolerance) {
        std::sort(changes_.begin(), changes_.end(), [](const Change& a, const Change& b) { return a.u < b.u; });
        Root root;
        Polynomial sum = base_;
        double start = 0.0;
        size_t next = 0;
        while (true) {
            const double end = next < changes_.size() ? changes_[next].u : 1.0;
            if (end > start) {
                BernsteinRootStats stats;
                const auto u = firstBernsteinRoot<Degree>(sum, start, end, tolerance, &stats);
                root.pieces += 1 + stats.subdivisions + stats.evaluations;
                if (u) {
                    root.found = true;
                    root.u = *u;
                    return root;
                }
            }
            if (next == changes_.size()) return root;
            // Every change at this u at once.
            const double at = changes_[next].u;
            for (; next < changes_.size() && changes_[next].u == at; ++next) {
                const Polynomial& p = terms_[changes_[next].term];
                const double sign = changes_[next].sign;
                for (int k = 0; k <= Degree; ++k) sum[k] += sign * p[k];
            }
            start = std::max(start, at);
        }
    }

private:
    struct Change {
        double u;
        uint32_t term;
        double sign;  ///< +1: the term starts here, -1: it ends
    };
    Polynomial base_{};
    std::vector<Polynomial> terms_;
    std::vector<Change> changes_;
};

/// The polynomial of degree 2 Degree in u of a polynomial of degree Degree
/// in q, where q(u) = q0 + q1 u + q2 u^2 (a squared distance along a ray):
/// p(q(u)) by Horner's rule in polynomials.
template <int Degree>
Monomials<2 * Degree> composeWithQuadratic(const Monomials<Degree>& p, double q0, double q1, double q2) {
    Monomials<2 * Degree> r{};
    r[0] = p[Degree];
    int degree = 0;
    for (int k = Degree - 1; k >= 0; --k) {
        // r = r * q + p[k]
        Monomials<2 * Degree> next{};
        for (int i = 0; i <= degree; ++i) {
            next[i] += r[i] * q0;
            next[i + 1] += r[i] * q1;
            next[i + 2] += r[i] * q2;
        }
        next[0] += p[k];
        r = next;
        degree += 2;
    }
    return r;
}

}  // namespace isotrace::geometry
