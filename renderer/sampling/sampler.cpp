#include "renderer/sampling/sampler.h"

#include <array>

namespace isotrace {

namespace {

// Laine-Karras style hash in which every bit is changed only by less
// significant bits; applied to reversed bits it is a nested uniform scramble.
inline uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Sobol dimension 1 (primitive polynomial x + 1) is linear over bits: the
// value of an index is the xor of direction numbers v_k for the bits k set
// in it (v_1 = 1/2, v_k = v_{k-1} xor v_{k-1} / 2). A sample needs it in
// bit-reversed form of a bit-reversed index, which is linear as well, so
// both come from four tables of 256 entries, one per byte of the index: the
// scrambled index has all 32 bits in play, and a loop over them with a
// branch per bit took an eighth of a small render's time.
using ByteTables = std::array<std::array<uint32_t, 256>, 4>;
struct Dimension1Tables {
    ByteTables plain;     // index -> sobol1(index)
    ByteTables reversed;  // w -> reverse(sobol1(reverse(w)))
};
const Dimension1Tables& dimension1Tables() {
    static const Dimension1Tables tables = [] {
        std::array<uint32_t, 32> v{};
        v[0] = 1u << 31;
        for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        Dimension1Tables t{};
        for (int j = 0; j < 4; ++j)
            for (uint32_t b = 0; b < 256; ++b)
                for (int k = 0; k < 8; ++k)
                    if (b & (1u << k)) {
                        t.plain[j][b] ^= v[8 * j + k];
                        // Bit 8j + k of w is bit 31 - 8j - k of reverse(w).
                        t.reversed[j][b] ^= reverseBits(v[31 - 8 * j - k]);
                    }
        return t;
    }();
    return tables;
}

uint32_t byByte(const ByteTables& t, uint32_t index) {
    return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
}

constexpr double kToUnit = 1.0 / 4294967296.0;  // 2^-32
constexpr double kOneMinusEpsilon = 0x1.fffffffffffffp-1;

inline double toUnit(uint32_t v) { return std::min(v * kToUnit, kOneMinusEpsilon); }

}  // namespace

uint32_t owenScramble(uint32_t v, uint32_t seed) { return reverseBits(laineKarrasPermutation(reverseBits(v), seed)); }

uint32_t sobolDimension0(uint32_t index) { return reverseBits(index); }

uint32_t sobolDimension1(uint32_t index) { return byByte(dimension1Tables().plain, index); }

// A sample of dimensions 0 and 1 is owenScramble(sobolN(index), seed) with
// index = owenScramble(sampleIndex, seed'), written out so that no bits are
// reversed twice. With w = laineKarras(reverse(sampleIndex), seed'), the
// index is reverse(w), and
//   dimension 0: reverse(laineKarras(reverse(w), seed)),
//   dimension 1: reverse(laineKarras(reverse(sobol1(reverse(w))), seed)).
// A camera sample's scrambling was a fifth of a 1-spp Whitted frame's
// per-pixel work; the values are the same bits as the composition.

double Sampler::get1D() {
    const uint32_t d = dimension_++;
    const uint64_t h = hashValues(pixelHash_, d);
    if (type_ == SamplerType::Independent) return toUnit(static_cast<uint32_t>(hashValues(h, sampleIndex_) >> 32));
    const uint32_t w = laineKarrasPermutation(reversedIndex_, static_cast<uint32_t>(h));
    return toUnit(reverseBits(laineKarrasPermutation(reverseBits(w), static_cast<uint32_t>(h >> 32))));
}

Eigen::Vector2d Sampler::get2D() {
    const uint32_t d = dimension_;
    dimension_ += 2;
    const uint64_t h = hashValues(pixelHash_, d);
    if (type_ == SamplerType::Independent) {
        const uint64_t r = hashValues(h, sampleIndex_);
        return {toUnit(static_cast<uint32_t>(r >> 32)), toUnit(static_cast<uint32_t>(r))};
    }
    const uint32_t w = laineKarrasPermutation(reversedIndex_, static_cast<uint32_t>(h));
    const uint64_t h2 = mixBits(h);
    return {toUnit(reverseBits(laineKarrasPermutation(reverseBits(w), static_cast<uint32_t>(h >> 32)))),
            toUnit(reverseBits(laineKarrasPermutation(byByte(dimension1Tables().reversed, w), static_cast<uint32_t>(h2))))};
}

}  // namespace isotrace
