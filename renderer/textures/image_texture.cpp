// "image": an image projected onto the surface along the three object axes
// and blended by the normal (triplanar mapping), since implicit surfaces
// have no UVs. Lookups go through OpenImageIO's TextureSystem: MIP-mapped
// and filtered over the pixel's footprint, tiles cached and shared.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/texture.h>
#include <cmath>

#include "renderer/texture.h"

namespace isotrace {

namespace {

using OIIO::TextureOpt;
using OIIO::TextureSystem;

// The process's texture system, shared by every scene (it caches tiles).
TextureSystem& textureSystem() {
    static TextureSystem* system = [] {
        TextureSystem* ts = TextureSystem::create(true);
        ts->attribute("automip", 1);  // MIP-map plain images on first use
        return ts;
    }();
    return *system;
}

double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

class ImageTexture final : public Texture {
public:
    ImageTexture(const std::string& file, int channels, bool srgb, double scale, double sharpness, RGB minimum,
                 RGB maximum)
        : channels_(channels), srgb_(srgb), inverseScale_(1.0 / scale), sharpness_(sharpness), minimum_(minimum),
          maximum_(maximum) {
        handle_ = textureSystem().get_texture_handle(OIIO::ustring(file));
    }

    RGB evaluate(const ShadingPoint& p) const override {
        const Vec3 q = p.objectPosition * inverseScale_;
        const Vec3 n = p.objectNormal.cwiseAbs();
        // Blend weights |n_i|^sharpness: sharper seams as it grows.
        Vec3 w(std::pow(n.x(), sharpness_), std::pow(n.y(), sharpness_), std::pow(n.z(), sharpness_));
        const double total = w.sum();
        if (!(total > 0)) w = Vec3(0, 0, 1);
        else w /= total;
        const float width = float(p.footprint * inverseScale_);
        TextureSystem& ts = textureSystem();
        TextureSystem::Perthread* thread = ts.get_perthread_info();
        RGB sum = RGB::Zero();
        const double coordinates[3][2] = {{q.z(), q.y()}, {q.x(), q.z()}, {q.x(), q.y()}};
        for (int axis = 0; axis < 3; ++axis) {
            if (w[axis] < 1e-4) continue;
            TextureOpt options;
            options.swrap = options.twrap = TextureOpt::WrapPeriodic;
            options.interpmode = TextureOpt::InterpBilinear;  // B-spline bicubic would blur texels
            float texel[3] = {0, 0, 0};
            ts.texture(handle_, thread, options, float(coordinates[axis][0]), float(1.0 - coordinates[axis][1]), width,
                       0.0f, 0.0f, width, channels_ == 1 ? 1 : 3, texel);
            const RGB value = channels_ == 1 ? RGB::Constant(texel[0]) : RGB(texel[0], texel[1], texel[2]);
            sum += w[axis] * value;
        }
        if (srgb_)
            for (int c = 0; c < 3; ++c) sum[c] = srgbToLinear(sum[c]);
        return sum;
    }
    int channels() const override { return channels_; }
    RGB minimum() const override { return minimum_; }
    RGB maximum() const override { return maximum_; }

private:
    TextureSystem::TextureHandle* handle_ = nullptr;
    int channels_;
    bool srgb_;
    double inverseScale_, sharpness_;
    RGB minimum_, maximum_;
};

}  // namespace

std::shared_ptr<const Texture> readImageTexture(geometry::JsonObjectReader& r, const MaterialContext& context) {
    const std::string name = r.string("file");
    const std::filesystem::path path = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name)
                                                                                 : context.directory / name;
    const double scale = r.positiveNumber("scale", 1.0);
    const double sharpness = r.positiveNumber("sharpness", 4.0);
    if (sharpness > 64) r.fail("sharpness", "must be at most 64");
    if (!std::filesystem::is_regular_file(path)) r.fail("file", "cannot read \"" + path.string() + "\": no such file");
    // Read the image once to validate it: channels, and values a material
    // parameter can be checked against (NaN and infinity refused).
    OIIO::ImageBuf image(path.string());
    if (!image.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        r.fail("file", "cannot read \"" + path.string() + "\": " + image.geterror());
    const OIIO::ImageSpec& spec = image.spec();
    int channels = spec.nchannels;
    if (channels == 4) channels = 3;  // alpha is ignored
    if (channels != 1 && channels != 3)
        r.fail("file", "\"" + path.string() + "\" has " + std::to_string(spec.nchannels) +
                           " channels; a texture needs 1 (grey), 3 (RGB) or 4 (RGBA)");
    const OIIO::ImageBufAlgo::PixelStats stats = OIIO::ImageBufAlgo::computePixelStats(image);
    for (int c = 0; c < spec.nchannels; ++c)
        if (stats.nancount[c] > 0 || stats.infcount[c] > 0)
            r.fail("file", "\"" + path.string() + "\" holds NaN or infinite values");
    const bool srgb = spec.get_string_attribute("oiio:ColorSpace") == "sRGB";
    RGB lowest, highest;
    for (int c = 0; c < 3; ++c) {
        const int source = channels == 1 ? 0 : c;
        lowest[c] = srgb ? srgbToLinear(stats.min[source]) : stats.min[source];
        highest[c] = srgb ? srgbToLinear(stats.max[source]) : stats.max[source];
    }
    return std::make_shared<ImageTexture>(path.string(), channels, srgb, scale, sharpness, lowest, highest);
}

}  // namespace isotrace
