// Algebraic surfaces: a polynomial in x, y, z given by its terms (quadrics
// and the classic presets are polynomials too). Values are not distances;
// range and Lipschitz bounds come from interval arithmetic on the terms and
// on the terms of the three partial derivatives.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

struct PolynomialTerm {
    double coefficient = 0.0;
    std::array<int, 3> powers{0, 0, 0};
};

class Polynomial {
public:
    static constexpr int kMaxDegree = 24;

    Polynomial() = default;
    explicit Polynomial(std::vector<PolynomialTerm> terms);  // merges like terms

    static Polynomial constant(double c);
    static Polynomial variable(int axis);  ///< x, y or z

    const std::vector<PolynomialTerm>& terms() const { return terms_; }
    int degree() const;
    Polynomial derivative(int axis) const;

    friend Polynomial operator+(const Polynomial& a, const Polynomial& b);
    friend Polynomial operator-(const Polynomial& a, const Polynomial& b);
    friend Polynomial operator*(const Polynomial& a, const Polynomial& b);
    friend Polynomial operator*(double s, const Polynomial& a);
    Polynomial power(int n) const;

    double evaluate(const Vec3& p) const;
    Interval evaluate(const Box3& box) const;

private:
    std::vector<PolynomialTerm> terms_;
    std::array<int, 3> maxPower_{0, 0, 0};  ///< highest power of each variable
    // Point evaluation, split for speed: the constant, the terms in one
    // variable as dense coefficients by power (Horner's rule), and the
    // terms mixing variables with the powers they need. Goursat's tangle
    // and its kin are sums of one-variable terms only.
    double constant_ = 0.0;
    std::array<std::vector<double>, 3> univariate_;  ///< coefficient of x_a^k at k (k >= 1)
    std::vector<PolynomialTerm> mixed_;
    std::array<int, 3> maxMixedPower_{0, 0, 0};
};

struct PolynomialField {
    PolynomialField(Polynomial p, const Box3& domain);

    const Polynomial& polynomial() const { return terms_->polynomial; }
    double value(const Vec3& p) const { return terms_->polynomial.evaluate(p); }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    Interval range(const Box3& box) const { return terms_->polynomial.evaluate(box); }
    double lipschitz(const Box3& box) const;
    Box3 bounds() const { return domain; }

    Box3 domain;  ///< the surface is sought inside this box only

private:
    // Shared, not inline: every cell's pruned program copies its leaves,
    // and four polynomials inline made each leaf of any kind 832 bytes
    // (most of a small CSG scene's start-up was those copies' page faults).
    struct Terms {
        Polynomial polynomial;
        std::array<Polynomial, 3> partials;
    };
    std::shared_ptr<const Terms> terms_;
};

}  // namespace isotrace::geometry
