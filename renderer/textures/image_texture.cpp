// "image": an image projected onto the surface along the three object axes
// and blended by the normal (triplanar mapping), since implicit surfaces
// have no UVs, or, with "mapping": "uv", placed by a mesh's texture
// coordinates. Lookups go through OpenImageIO's TextureSystem (in the
// module openImageIo() loads): MIP-mapped and filtered over the pixel's
// footprint, tiles cached and shared.
#include <cmath>
#include <limits>

#include "renderer/image/image_file.h"
#include "renderer/image/openimageio_library.h"
#include "renderer/texture.h"

namespace isotrace {

namespace {

double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

class ImageTexture final : public Texture {
public:
    ImageTexture(const std::string& file, int channels, bool srgb, bool uvMapping, double scale, double sharpness,
                 RGB minimum, RGB maximum)
        : channels_(channels), srgb_(srgb), uvMapping_(uvMapping), inverseScale_(1.0 / scale), sharpness_(sharpness),
          minimum_(minimum), maximum_(maximum) {
        image_ = openImageIo().openTexture(file);
    }

    RGB evaluate(const ShadingPoint& p) const override {
        // Surfaces without texture coordinates fall back to the projection.
        if (uvMapping_ && p.hasUv) {
            // v runs up the image, as in OBJ files and Blender; rows run down.
            return decoded(lookup(p.uv.x() * inverseScale_, 1.0 - p.uv.y() * inverseScale_, p.uvFootprint * inverseScale_));
        }
        const Vec3 q = p.objectPosition * inverseScale_;
        const Vec3 n = p.objectNormal.cwiseAbs();
        // Blend weights |n_i|^sharpness: sharper seams as it grows.
        Vec3 w(std::pow(n.x(), sharpness_), std::pow(n.y(), sharpness_), std::pow(n.z(), sharpness_));
        const double total = w.sum();
        if (!(total > 0)) w = Vec3(0, 0, 1);
        else w /= total;
        const double width = p.footprint * inverseScale_;
        RGB sum = RGB::Zero();
        const double coordinates[3][2] = {{q.z(), q.y()}, {q.x(), q.z()}, {q.x(), q.y()}};
        for (int axis = 0; axis < 3; ++axis)
            if (w[axis] >= 1e-4) sum += w[axis] * lookup(coordinates[axis][0], 1.0 - coordinates[axis][1], width);
        return decoded(sum);
    }
    int channels() const override { return channels_; }
    RGB minimum() const override { return minimum_; }
    RGB maximum() const override { return maximum_; }

private:
    /// The filtered texel at (s, t), as stored (grey spread to three channels).
    RGB lookup(double s, double t, double width) const {
        float texel[3] = {0, 0, 0};
        image_->lookup(float(s), float(t), float(width), channels_ == 1 ? 1 : 3, texel);
        return channels_ == 1 ? RGB::Constant(texel[0]) : RGB(texel[0], texel[1], texel[2]);
    }
    /// Linear values from the file's encoding.
    RGB decoded(RGB value) const {
        if (srgb_)
            for (int c = 0; c < 3; ++c) value[c] = srgbToLinear(value[c]);
        return value;
    }

    std::unique_ptr<TextureImage> image_;
    int channels_;
    bool srgb_;
    bool uvMapping_;
    double inverseScale_, sharpness_;
    RGB minimum_, maximum_;
};

}  // namespace

std::shared_ptr<const Texture> readImageTexture(geometry::JsonObjectReader& r, const MaterialContext& context) {
    const std::string name = r.string("file");
    const std::filesystem::path path = std::filesystem::path(name).is_absolute() ? std::filesystem::path(name)
                                                                                 : context.directory / name;
    const bool uvMapping = r.choice("mapping", {"triplanar", "uv"}, "triplanar") == "uv";
    const std::string colorSpace = r.choice("color_space", {"auto", "srgb", "linear"}, "auto");
    const double scale = r.positiveNumber("scale", 1.0);
    const double sharpness = r.positiveNumber("sharpness", 4.0);
    if (sharpness > 64) r.fail("sharpness", "must be at most 64");
    if (!std::filesystem::is_regular_file(path)) r.fail("file", "cannot read \"" + path.string() + "\": no such file");
    // Read the image once to validate it: channels, and values a material
    // parameter can be checked against (NaN and infinity refused).
    ImageFile image;
    try {
        image = readImageFile(path.string());
    } catch (const std::exception& e) {
        r.fail("file", "cannot read \"" + path.string() + "\": " + e.what());
    }
    int channels = image.channels();
    if (channels == 4) channels = 3;  // alpha is ignored
    if (channels != 1 && channels != 3)
        r.fail("file", "\"" + path.string() + "\" has " + std::to_string(image.channels()) +
                           " channels; a texture needs 1 (grey), 3 (RGB) or 4 (RGBA)");
    float minimum[3], maximum[3];
    std::fill_n(minimum, 3, std::numeric_limits<float>::infinity());
    std::fill_n(maximum, 3, -std::numeric_limits<float>::infinity());
    const size_t stride = size_t(image.channels());
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const float v = image.pixels[i];
        if (!std::isfinite(v)) r.fail("file", "\"" + path.string() + "\" holds NaN or infinite values");
        const size_t c = i % stride;
        if (c < 3) {
            minimum[c] = std::min(minimum[c], v);
            maximum[c] = std::max(maximum[c], v);
        }
    }
    // Display-encoded files (PNG, JPEG) hold sRGB values; OpenImageIO says
    // so, EXR files read without it are linear.
    bool srgb = false;
    for (const auto& [name, value] : image.strings)
        if (name == "oiio:ColorSpace") srgb = value == "sRGB";
    // Data maps (roughness) in PNG files are not colours: "linear" reads them as they are.
    if (colorSpace != "auto") srgb = colorSpace == "srgb";
    RGB lowest, highest;
    for (int c = 0; c < 3; ++c) {
        const int source = channels == 1 ? 0 : c;
        lowest[c] = srgb ? srgbToLinear(minimum[source]) : minimum[source];
        highest[c] = srgb ? srgbToLinear(maximum[source]) : maximum[source];
    }
    return std::make_shared<ImageTexture>(path.string(), channels, srgb, uvMapping, scale, sharpness, lowest, highest);
}

}  // namespace isotrace
