#include "renderer/sampling/sampler.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <set>

using namespace isotrace;

TEST(Sampler, ValuesDependOnlyOnSeedPixelSampleAndDimension) {
    for (SamplerType type : {SamplerType::Sobol, SamplerType::Independent}) {
        Sampler a(type, 9), b(type, 9);
        // Different call histories must not matter.
        b.startPixelSample(5, 5, 3);
        b.get2D();
        a.startPixelSample(1, 2, 7);
        b.startPixelSample(1, 2, 7);
        for (int d = 0; d < 20; ++d) {
            const auto x = a.get2D(), y = b.get2D();
            EXPECT_EQ(x, y);
        }
        Sampler c(type, 10);
        c.startPixelSample(1, 2, 7);
        a.startPixelSample(1, 2, 7);
        EXPECT_NE(a.get2D(), c.get2D()) << "the seed must change the numbers";
    }
}

TEST(Sampler, ValuesLieInTheUnitInterval) {
    Sampler s(SamplerType::Sobol, 1);
    for (int i = 0; i < 1000; ++i) {
        s.startPixelSample(i % 17, i % 13, i);
        for (int d = 0; d < 10; ++d) {
            const double v = s.get1D();
            ASSERT_GE(v, 0.0);
            ASSERT_LT(v, 1.0);
        }
    }
}

// The first 2^m Owen-scrambled Sobol points of a dimension pair put exactly
// one point in each cell of every elementary grid (1 x 2^m ... 2^m x 1).
TEST(Sampler, SobolPairsAreStratifiedInEveryElementaryGrid) {
    constexpr int m = 6, n = 1 << m;
    for (int pixel = 0; pixel < 8; ++pixel) {
        Sampler s(SamplerType::Sobol, 3);
        std::vector<Eigen::Vector2d> points(n);
        for (int dimensionPair = 0; dimensionPair < 3; ++dimensionPair) {
            for (int i = 0; i < n; ++i) {
                s.startPixelSample(pixel, 0, i);
                for (int k = 0; k < dimensionPair; ++k) s.get2D();
                points[i] = s.get2D();
            }
            for (int bitsX = 0; bitsX <= m; ++bitsX) {
                const int cellsX = 1 << bitsX, cellsY = 1 << (m - bitsX);
                std::set<int> cells;
                for (const auto& p : points) cells.insert(int(p.x() * cellsX) * cellsY + int(p.y() * cellsY));
                EXPECT_EQ(cells.size(), size_t(n)) << "pixel " << pixel << " pair " << dimensionPair << " grid "
                                                   << cellsX << "x" << cellsY;
            }
        }
    }
}

// Dimension 1 is read from byte tables; the definition is the xor of the
// direction numbers v_k (v_1 = 1/2, v_k = v_{k-1} xor v_{k-1} / 2) of the
// index's set bits, and all 32 bits of a scrambled index are in play.
TEST(Sampler, SobolDimension1MatchesItsDirectionNumbers) {
    uint32_t v[32];
    v[0] = 1u << 31;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    uint64_t state = 12345;
    for (int i = 0; i < 10000; ++i) {
        state = mixBits(state + 1);
        const uint32_t index = i < 64 ? uint32_t(i) : static_cast<uint32_t>(state >> 32);
        uint32_t expected = 0;
        for (int k = 0; k < 32; ++k)
            if (index & (1u << k)) expected ^= v[k];
        ASSERT_EQ(sobolDimension1(index), expected) << "index " << index;
    }
}

// A Sobol sample is the scrambled sample index's point in dimensions 0 and
// 1, each scrambled again: owenScramble(sobolN(owenScramble(i, low)), seed)
// with the dimension's hash split into seeds. The sampler computes it
// without reversing bits twice; the values must be the same bits.
TEST(Sampler, SobolValuesAreTheScrambledSequence) {
    auto unit = [](uint32_t v) { return std::min(v / 4294967296.0, 0x1.fffffffffffffp-1); };
    for (const uint64_t seed : {0ull, 9ull})
        for (const uint32_t index : {0u, 1u, 5u, 255u, 256u, 70000u, 4000000000u})
            for (int pixel = 0; pixel < 50; ++pixel) {
                const int x = pixel * 37 % 500, y = pixel * 11 % 300;
                Sampler sampler(SamplerType::Sobol, seed);
                sampler.startPixelSample(x, y, index);
                const uint64_t pixelHash = hashValues(seed, uint64_t(x), uint64_t(y));
                for (uint32_t d = 0; d < 7; d += 2) {
                    const uint64_t h = hashValues(pixelHash, d);
                    const uint32_t scrambled = owenScramble(index, uint32_t(h));
                    const Eigen::Vector2d u = sampler.get2D();
                    ASSERT_EQ(u.x(), unit(owenScramble(sobolDimension0(scrambled), uint32_t(h >> 32))));
                    ASSERT_EQ(u.y(), unit(owenScramble(sobolDimension1(scrambled), uint32_t(mixBits(h)))));
                }
                const uint64_t h = hashValues(pixelHash, 8);
                ASSERT_EQ(sampler.get1D(), unit(owenScramble(sobolDimension0(owenScramble(index, uint32_t(h))), uint32_t(h >> 32))));
            }
}

TEST(Sampler, IndependentValuesHaveTheRightMoments) {
    Sampler s(SamplerType::Independent, 4);
    double sum = 0, sum2 = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        s.startPixelSample(i % 100, i / 100, i);
        const double v = s.get1D();
        sum += v;
        sum2 += v * v;
    }
    // Mean 1/2 and second moment 1/3, within 5 standard errors.
    EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
    EXPECT_NEAR(sum2 / n, 1.0 / 3.0, 5 * std::sqrt(4.0 / 45 / n));
}
