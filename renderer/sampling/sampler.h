// Deterministic sample generation: every number depends only on (seed,
// pixel, sample index, dimension), never on threads, tiles or order.
//
// "sobol": Owen-scrambled 2D Sobol points per dimension pair, with the
// sample index shuffled per pixel and dimension (Burley 2020, "Practical
// Hash-based Owen Scrambling"), so each pair is a well-stratified net.
// "independent": hashed uniform numbers, for comparison and debugging.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace isotrace {

enum class SamplerType { Sobol, Independent };

/// 64-bit finaliser (MurmurHash3's fmix64): a bijective avalanche mix.
inline uint64_t mixBits(uint64_t v) {
    v ^= v >> 33;
    v *= 0xff51afd7ed558ccdULL;
    v ^= v >> 33;
    v *= 0xc4ceb9fe1a85ec53ULL;
    v ^= v >> 33;
    return v;
}
inline uint64_t hashValues(uint64_t a, uint64_t b) { return mixBits(a ^ mixBits(b + 0x9e3779b97f4a7c15ULL)); }
inline uint64_t hashValues(uint64_t a, uint64_t b, uint64_t c) { return hashValues(hashValues(a, b), c); }
inline uint64_t hashValues(uint64_t a, uint64_t b, uint64_t c, uint64_t d) { return hashValues(hashValues(a, b, c), d); }

/// The bits of v in reverse order.
inline uint32_t reverseBits(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
    v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
    return (v >> 16) | (v << 16);
}

class Sampler {
public:
    Sampler(SamplerType type, uint64_t seed) : type_(type), seed_(seed) {}

    void startPixelSample(int x, int y, uint32_t sampleIndex) {
        pixelHash_ = hashValues(seed_, static_cast<uint64_t>(x), static_cast<uint64_t>(y));
        sampleIndex_ = sampleIndex;
        reversedIndex_ = reverseBits(sampleIndex);
        dimension_ = 0;
    }
    double get1D();
    Eigen::Vector2d get2D();
    /// Passes over the next two dimensions unused (a pinhole camera's lens
    /// sample), so that later ones stay the dimensions they would be.
    void skip2D() { dimension_ += 2; }

private:
    SamplerType type_;
    uint64_t seed_;
    uint64_t pixelHash_ = 0;
    uint32_t sampleIndex_ = 0;
    uint32_t reversedIndex_ = 0;  // the sample index's bits reversed, the start of every Sobol dimension's scramble
    uint32_t dimension_ = 0;
};

/// Nested uniform (Owen) scrambling of a 32-bit fixed-point value.
uint32_t owenScramble(uint32_t v, uint32_t seed);
/// The first two dimensions of the Sobol sequence, as 32-bit fixed point.
uint32_t sobolDimension0(uint32_t index);
uint32_t sobolDimension1(uint32_t index);

}  // namespace isotrace
