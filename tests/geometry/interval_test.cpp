#include "geometry/interval.h"

#include <gtest/gtest.h>

#include <random>

using namespace isotrace::geometry;

// Every operation's result interval contains the operation applied to
// members of the operands.
TEST(Interval, OperationsContainSampledResults) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-3.0, 3.0), t(0.0, 1.0);
    for (int trial = 0; trial < 2000; ++trial) {
        double a0 = u(rng), a1 = u(rng), b0 = u(rng), b1 = u(rng);
        if (a0 > a1) std::swap(a0, a1);
        if (b0 > b1) std::swap(b0, b1);
        const Interval a(a0, a1), b(b0, b1);
        const double x = a0 + t(rng) * (a1 - a0), y = b0 + t(rng) * (b1 - b0);
        SCOPED_TRACE(::testing::Message() << "trial " << trial << " a=" << a << " b=" << b);
        EXPECT_TRUE((a + b).contains(x + y));
        EXPECT_TRUE((a - b).contains(x - y));
        EXPECT_TRUE((a * b).contains(x * y));
        EXPECT_TRUE(min(a, b).contains(std::min(x, y)));
        EXPECT_TRUE(max(a, b).contains(std::max(x, y)));
        for (int n = 0; n <= 6; ++n) EXPECT_TRUE(widened(pow(a, n)).contains(std::pow(x, n))) << "n=" << n;
    }
}

TEST(Interval, EvenPowerOfStraddlingIntervalStartsAtZero) {
    const Interval p = pow(Interval(-2.0, 1.0), 2);
    EXPECT_EQ(p.lo, 0.0);
    EXPECT_EQ(p.hi, 4.0);
    EXPECT_EQ(pow(Interval(-2.0, -1.0), 3).lo, -8.0);
}
