// "noise": Perlin's gradient noise summed over octaves (fractal Brownian
// motion) in object space, blending two values: marble, stone, rust.
#include <array>
#include <cmath>
#include <cstdint>

#include "renderer/textures/two_colors.h"

namespace isotrace {

namespace {

class NoiseTexture final : public Texture {
public:
    NoiseTexture(const TwoColors& colors, double scale, int octaves, uint32_t seed)
        : colors_(colors), inverseScale_(1.0 / scale), octaves_(octaves) {
        // A permutation of 0..255 shuffled by a small LCG from the seed.
        for (int i = 0; i < 256; ++i) permutation_[i] = uint8_t(i);
        uint64_t state = 0x9E3779B97F4A7C15ull ^ seed;
        for (int i = 255; i > 0; --i) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            const int j = int((state >> 33) % uint64_t(i + 1));
            std::swap(permutation_[i], permutation_[j]);
        }
    }

    RGB evaluate(const ShadingPoint& p) const override {
        Vec3 q = p.objectPosition * inverseScale_;
        double sum = 0.0, amplitude = 0.5, norm = 0.0;
        for (int o = 0; o < octaves_; ++o) {
            sum += amplitude * noise(q);
            norm += amplitude;
            amplitude *= 0.5;
            q *= 2.0;
        }
        // Perlin noise stays within about [-1, 1]; map to [0, 1].
        const double t = std::clamp(0.5 + 0.5 * sum / norm * 1.4, 0.0, 1.0);
        return colors_.mix(t);
    }
    int channels() const override { return colors_.channels; }
    RGB minimum() const override { return colors_.a.min(colors_.b); }
    RGB maximum() const override { return colors_.a.max(colors_.b); }

private:
    int hash(int x, int y, int z) const {
        return permutation_[(permutation_[(permutation_[x & 255] + y) & 255] + z) & 255];
    }
    static double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }
    // Dot product with one of Perlin's 12 edge gradients.
    static double gradient(int h, double x, double y, double z) {
        switch (h % 12) {
            case 0: return x + y;
            case 1: return -x + y;
            case 2: return x - y;
            case 3: return -x - y;
            case 4: return x + z;
            case 5: return -x + z;
            case 6: return x - z;
            case 7: return -x - z;
            case 8: return y + z;
            case 9: return -y + z;
            case 10: return y - z;
            default: return -y - z;
        }
    }
    double noise(const Vec3& p) const {
        const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
        const int x = int(int64_t(fx) & 255), y = int(int64_t(fy) & 255), z = int(int64_t(fz) & 255);
        const double dx = p.x() - fx, dy = p.y() - fy, dz = p.z() - fz;
        const double u = fade(dx), v = fade(dy), w = fade(dz);
        auto corner = [&](int i, int j, int k) { return gradient(hash(x + i, y + j, z + k), dx - i, dy - j, dz - k); };
        auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
        return lerp(w,
                    lerp(v, lerp(u, corner(0, 0, 0), corner(1, 0, 0)), lerp(u, corner(0, 1, 0), corner(1, 1, 0))),
                    lerp(v, lerp(u, corner(0, 0, 1), corner(1, 0, 1)), lerp(u, corner(0, 1, 1), corner(1, 1, 1))));
    }

    TwoColors colors_;
    double inverseScale_;
    int octaves_;
    std::array<uint8_t, 256> permutation_;
};

}  // namespace

std::shared_ptr<const Texture> readNoiseTexture(geometry::JsonObjectReader& r, const MaterialContext&) {
    const double scale = r.positiveNumber("scale", 1.0);
    const int octaves = static_cast<int>(r.integer("octaves", 4, 1, 16));
    const uint32_t seed = static_cast<uint32_t>(r.integer("seed", 0, 0, 0xffffffffll));
    return std::make_shared<NoiseTexture>(TwoColors::read(r), scale, octaves, seed);
}

}  // namespace isotrace
