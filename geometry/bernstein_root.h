// The first root of a polynomial of one variable on an interval, isolated
// in the Bernstein basis: over [a, b] the polynomial lies in the convex hull
// of its Bernstein coefficients, so coefficients of one sign prove the
// interval free of roots, and one sign change among them proves exactly one
// root (Descartes' rule for the Bernstein basis). Anything else is halved
// (de Casteljau), left half first. Isolated roots are refined by
// bracketedRoot on the polynomial itself.
#pragma once

#include <array>
#include <optional>

#include "geometry/bracketed_root.h"

namespace isotrace::geometry {

/// p(u) = sum_k coefficients[k] u^k.
template <int Degree>
using Monomials = std::array<double, Degree + 1>;

template <int Degree>
double evaluatePolynomial(const Monomials<Degree>& c, double u) {
    double v = c[Degree];
    for (int k = Degree - 1; k >= 0; --k) v = v * u + c[k];
    return v;
}

/// Bernstein coefficients over [a, b] of a polynomial in monomial form.
template <int Degree>
std::array<double, Degree + 1> bernsteinOver(Monomials<Degree> c, double a, double b) {
    // p(a + w): Taylor shift by repeated synthetic division.
    for (int i = 0; i < Degree; ++i)
        for (int k = Degree - 1; k >= i; --k) c[k] += a * c[k + 1];
    // w = (b - a) v.
    const double h = b - a;
    double power = h;
    for (int k = 1; k <= Degree; ++k, power *= h) c[k] *= power;
    // b_i = sum_{k <= i} C(i, k) / C(Degree, k) c_k.
    std::array<double, Degree + 1> bernstein{};
    for (int i = 0; i <= Degree; ++i) {
        double ratio = 1.0, sum = c[0];  // C(i, 0) / C(n, 0)
        for (int k = 1; k <= i; ++k) {
            ratio *= double(i - k + 1) / double(Degree - k + 1);
            sum += ratio * c[k];
        }
        bernstein[i] = sum;
    }
    return bernstein;
}

struct BernsteinRootStats {
    int subdivisions = 0;
    int evaluations = 0;
};

/// The first u in [a, b] where p changes sign (or is zero), to within
/// `tolerance`; none when the Bernstein hulls prove there is none. Where
/// halving reaches `tolerance` with the sign unresolved (two roots closer
/// than that, or a touching one), the piece's start is taken as a root, so
/// a surface is never missed for a rounding of its coefficients.
/// With anyRoot (an occlusion query), the middle of the first piece whose
/// ends differ in sign: a root lies in it, found without refining.
template <int Degree>
std::optional<double> firstBernsteinRoot(const Monomials<Degree>& p, double a, double b, double tolerance,
                                         BernsteinRootStats* stats = nullptr, bool anyRoot = false) {
    using Coefficients = std::array<double, Degree + 1>;
    struct Piece {
        double lo, hi;
        Coefficients c;
    };
    // Depth-first, left half first: at most one pending right half per level.
    constexpr int kMaxDepth = 60;
    Piece stack[kMaxDepth + 1];
    int top = 0;
    stack[top++] = {a, b, bernsteinOver<Degree>(p, a, b)};
    while (top > 0) {
        const Piece piece = stack[--top];
        const Coefficients& c = piece.c;
        if (c[0] == 0.0) return piece.lo;
        int changes = 0;
        bool allPositive = true, allNegative = true;
        for (int k = 0; k <= Degree; ++k) {
            allPositive = allPositive && c[k] > 0;
            allNegative = allNegative && c[k] < 0;
            if (k > 0 && ((c[k] < 0) != (c[k - 1] < 0))) ++changes;
        }
        if (allPositive || allNegative) continue;
        const bool endsDiffer = (c[0] < 0) != (c[Degree] < 0) || c[Degree] == 0.0;
        if (anyRoot && endsDiffer) return c[Degree] == 0.0 ? piece.hi : 0.5 * (piece.lo + piece.hi);
        if (changes == 1 && endsDiffer) {
            const double fa = c[0], fb = c[Degree];
            if (fb == 0.0) return piece.hi;
            int evaluations = 0;
            const double root = bracketedRoot([&](double u) { return evaluatePolynomial<Degree>(p, u); }, piece.lo, fa,
                                              piece.hi, fb, 1e-3 * tolerance, &evaluations);
            if (stats) stats->evaluations += evaluations;
            return root;
        }
        if (piece.hi - piece.lo <= tolerance || top >= kMaxDepth - 1) {
            if (endsDiffer) {
                int evaluations = 0;
                const double root = bracketedRoot([&](double u) { return evaluatePolynomial<Degree>(p, u); },
                                                  piece.lo, c[0], piece.hi, c[Degree], 1e-3 * tolerance, &evaluations);
                if (stats) stats->evaluations += evaluations;
                return root;
            }
            return piece.lo;
        }
        // de Casteljau at the midpoint: the left half's coefficients are the
        // first of each row, the right half's the last.
        Coefficients left, right, row = c;
        for (int level = 0; level <= Degree; ++level) {
            left[level] = row[0];
            right[Degree - level] = row[Degree - level];
            for (int k = 0; k < Degree - level; ++k) row[k] = 0.5 * (row[k] + row[k + 1]);
        }
        const double mid = 0.5 * (piece.lo + piece.hi);
        if (stats) ++stats->subdivisions;
        stack[top++] = {mid, piece.hi, right};
        stack[top++] = {piece.lo, mid, left};
    }
    return std::nullopt;
}

}  // namespace isotrace::geometry
