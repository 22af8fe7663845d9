#include "geometry/fields/polynomial.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace isotrace::geometry;

// Point evaluation splits the terms (a constant, one-variable terms by
// Horner's rule, mixed terms by powers); it must agree with the plain sum
// of c x^i y^j z^k, for the tangle (one-variable terms only), a torus
// (mixed terms) and a polynomial with both and a lone constant.
TEST(Polynomial, EvaluationMatchesTheSumOfItsTerms) {
    const Polynomial x = Polynomial::variable(0), y = Polynomial::variable(1), z = Polynomial::variable(2);
    const Polynomial tangle = x.power(4) - 5.0 * x.power(2) + y.power(4) - 5.0 * y.power(2) + z.power(4) -
                              5.0 * z.power(2) + Polynomial::constant(11.8);
    const Polynomial r2 = x.power(2) + y.power(2) + z.power(2);
    const Polynomial torus = (r2 + Polynomial::constant(1 - 0.09)).power(2) - 4.0 * (x.power(2) + y.power(2));
    const Polynomial both = 3.0 * x.power(7) - 2.0 * x * y.power(3) * z + 0.5 * z.power(5) + Polynomial::constant(-4);
    for (const Polynomial* p : {&tangle, &torus, &both}) {
        for (const Vec3& at : {Vec3(0.3, -1.2, 2.1), Vec3(-2.5, 0.0, 1.0), Vec3(1e-3, 4.0, -0.7), Vec3(0, 0, 0)}) {
            double sum = 0.0, magnitude = 0.0;
            for (const PolynomialTerm& t : p->terms()) {
                const double term =
                    t.coefficient * std::pow(at.x(), t.powers[0]) * std::pow(at.y(), t.powers[1]) * std::pow(at.z(), t.powers[2]);
                sum += term;
                magnitude += std::abs(term);
            }
            EXPECT_NEAR(p->evaluate(at), sum, 1e-13 * magnitude) << at.transpose();
        }
    }
}
