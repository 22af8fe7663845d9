#include "geometry/fields/polynomial.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace isotrace::geometry {

Polynomial::Polynomial(std::vector<PolynomialTerm> terms) {
    std::map<std::array<int, 3>, double> merged;
    for (const PolynomialTerm& t : terms) {
        for (int p : t.powers)
            if (p < 0 || p > kMaxDegree)
                throw std::invalid_argument("polynomial powers must be whole numbers from 0 to " +
                                            std::to_string(kMaxDegree));
        merged[t.powers] += t.coefficient;
    }
    for (const auto& [powers, c] : merged) {
        if (c == 0.0) continue;
        terms_.push_back({c, powers});
        for (int a = 0; a < 3; ++a) maxPower_[a] = std::max(maxPower_[a], powers[a]);
        const int variables = int(powers[0] > 0) + int(powers[1] > 0) + int(powers[2] > 0);
        if (variables == 0) {
            constant_ += c;
        } else if (variables == 1) {
            const int a = powers[0] > 0 ? 0 : powers[1] > 0 ? 1 : 2;
            if (univariate_[a].size() <= size_t(powers[a])) univariate_[a].resize(size_t(powers[a]) + 1, 0.0);
            univariate_[a][size_t(powers[a])] += c;
        } else {
            mixed_.push_back({c, powers});
            for (int a = 0; a < 3; ++a) maxMixedPower_[a] = std::max(maxMixedPower_[a], powers[a]);
        }
    }
}

Polynomial Polynomial::constant(double c) { return Polynomial(std::vector<PolynomialTerm>{PolynomialTerm{c, {0, 0, 0}}}); }
Polynomial Polynomial::variable(int axis) {
    PolynomialTerm t{1.0, {0, 0, 0}};
    t.powers[axis] = 1;
    return Polynomial(std::vector<PolynomialTerm>{t});
}

int Polynomial::degree() const {
    int d = 0;
    for (const PolynomialTerm& t : terms_) d = std::max(d, t.powers[0] + t.powers[1] + t.powers[2]);
    return d;
}

Polynomial Polynomial::derivative(int axis) const {
    std::vector<PolynomialTerm> out;
    for (PolynomialTerm t : terms_) {
        if (t.powers[axis] == 0) continue;
        t.coefficient *= t.powers[axis];
        --t.powers[axis];
        out.push_back(t);
    }
    return Polynomial(std::move(out));
}

Polynomial operator+(const Polynomial& a, const Polynomial& b) {
    std::vector<PolynomialTerm> t = a.terms_;
    t.insert(t.end(), b.terms_.begin(), b.terms_.end());
    return Polynomial(std::move(t));
}
Polynomial operator*(double s, const Polynomial& a) {
    std::vector<PolynomialTerm> t = a.terms_;
    for (PolynomialTerm& term : t) term.coefficient *= s;
    return Polynomial(std::move(t));
}
Polynomial operator-(const Polynomial& a, const Polynomial& b) { return a + (-1.0) * b; }
Polynomial operator*(const Polynomial& a, const Polynomial& b) {
    std::vector<PolynomialTerm> t;
    for (const PolynomialTerm& x : a.terms_)
        for (const PolynomialTerm& y : b.terms_)
            t.push_back({x.coefficient * y.coefficient,
                         {x.powers[0] + y.powers[0], x.powers[1] + y.powers[1], x.powers[2] + y.powers[2]}});
    return Polynomial(std::move(t));
}
Polynomial Polynomial::power(int n) const {
    Polynomial r = constant(1.0);
    for (int i = 0; i < n; ++i) r = r * *this;
    return r;
}

double Polynomial::evaluate(const Vec3& p) const {
    double sum = constant_;
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& c = univariate_[a];
        if (c.size() < 2) continue;
        double horner = c.back();
        for (size_t k = c.size() - 1; k-- > 1;) horner = horner * p[a] + c[k];
        sum += horner * p[a];
    }
    if (mixed_.empty()) return sum;
    // Powers on the stack: evaluation allocates nothing.
    std::array<std::array<double, kMaxDegree + 1>, 3> pw;
    for (int a = 0; a < 3; ++a) {
        pw[a][0] = 1.0;
        for (int k = 1; k <= maxMixedPower_[a]; ++k) pw[a][k] = pw[a][k - 1] * p[a];
    }
    for (const PolynomialTerm& t : mixed_)
        sum += t.coefficient * pw[0][t.powers[0]] * pw[1][t.powers[1]] * pw[2][t.powers[2]];
    return sum;
}

Interval Polynomial::evaluate(const Box3& box) const {
    // Even powers of a straddling interval are taken whole (pow), which keeps
    // x^4 - 5 x^2 style terms far tighter than repeated multiplication.
    std::array<std::array<Interval, kMaxDegree + 1>, 3> pw;
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k <= maxPower_[a]; ++k) pw[a][k] = pow(box.axis(a), k);
    Interval sum(0.0);
    for (const PolynomialTerm& t : terms_)
        sum += t.coefficient * (pw[0][t.powers[0]] * pw[1][t.powers[1]] * pw[2][t.powers[2]]);
    return sum;
}

PolynomialField::PolynomialField(Polynomial p, const Box3& d) : domain(d) {
    std::array<Polynomial, 3> partials{p.derivative(0), p.derivative(1), p.derivative(2)};
    terms_ = std::make_shared<const Terms>(Terms{std::move(p), std::move(partials)});
}

double PolynomialField::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    const std::array<Polynomial, 3>& partials = terms_->partials;
    gradient = Vec3(partials[0].evaluate(p), partials[1].evaluate(p), partials[2].evaluate(p));
    return terms_->polynomial.evaluate(p);
}

double PolynomialField::lipschitz(const Box3& box) const {
    double sum2 = 0.0;
    for (const Polynomial& d : terms_->partials) {
        const double m = d.evaluate(box).magnitude();
        sum2 += m * m;
    }
    return std::sqrt(sum2);
}

}  // namespace isotrace::geometry
