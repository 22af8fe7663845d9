// The OpenImageIO module (isotrace_openimageio.so): the one place that
// links OpenImageIO. Loaded by openImageIo() on first use; it depends on
// nothing of the renderer but the interface header.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <stdexcept>

#include "renderer/image/openimageio_library.h"

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

class OpenImageIoTexture final : public TextureImage {
public:
    explicit OpenImageIoTexture(TextureSystem::TextureHandle* handle) : handle_(handle) {}

    void lookup(float s, float t, float width, int channels, float* out) const override {
        TextureSystem& ts = textureSystem();
        TextureOpt options;
        options.swrap = options.twrap = TextureOpt::WrapPeriodic;
        options.interpmode = TextureOpt::InterpBilinear;  // B-spline bicubic would blur texels
        ts.texture(handle_, ts.get_perthread_info(), options, s, t, width, 0.0f, 0.0f, width, channels, out);
    }

private:
    TextureSystem::TextureHandle* handle_;
};

OIIO::TypeDesc typeOf(SampleFormat format) {
    switch (format) {
        case SampleFormat::Float: return OIIO::TypeDesc::FLOAT;
        case SampleFormat::Half: return OIIO::TypeDesc::HALF;
        case SampleFormat::Byte: return OIIO::TypeDesc::UINT8;
    }
    return OIIO::TypeDesc::FLOAT;
}

class Library final : public OpenImageIoLibrary {
public:
    ImageFile read(const std::string& path, bool withPixels) override {
        auto in = OIIO::ImageInput::open(path);
        if (!in) throw std::runtime_error(path + ": cannot read image: " + OIIO::geterror());
        const OIIO::ImageSpec& spec = in->spec();
        ImageFile image;
        image.width = spec.width;
        image.height = spec.height;
        image.x = spec.x;
        image.y = spec.y;
        image.fullWidth = spec.full_width;
        image.fullHeight = spec.full_height;
        image.channelNames = spec.channelnames;
        image.floatingPoint = spec.format.is_floating_point();
        for (const OIIO::ParamValue& p : spec.extra_attribs)
            if (p.type() == OIIO::TypeDesc::STRING) image.strings.emplace_back(p.name().string(), p.get_string());
        if (image.width < 1 || image.height < 1 || image.channelNames.empty())
            throw std::runtime_error(path + ": cannot read image: it holds no pixels");
        if (!withPixels) return image;
        image.pixels.resize(size_t(spec.width) * spec.height * spec.nchannels);
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()))
            throw std::runtime_error(path + ": cannot read image: " + in->geterror());
        return image;
    }

    void write(const std::string& path, const std::string& temporary, const ImageFile& image,
               SampleFormat format) override {
        OIIO::ImageSpec spec(image.width, image.height, image.channels(), typeOf(format));
        spec.channelnames = image.channelNames;
        spec.x = image.x;
        spec.y = image.y;
        spec.full_x = 0;
        spec.full_y = 0;
        spec.full_width = image.fullWidth > 0 ? image.fullWidth : image.width;
        spec.full_height = image.fullHeight > 0 ? image.fullHeight : image.height;
        for (const auto& [name, value] : image.strings) spec.attribute(name, value);
        // The format follows `path`'s extension; the bytes go to `temporary`.
        auto out = OIIO::ImageOutput::create(path);
        if (!out) throw std::runtime_error(path + ": cannot write this image format (" + OIIO::geterror() + ")");
        if (!(out->open(temporary, spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) &&
              out->close()))
            throw std::runtime_error(path + ": cannot write image: " + out->geterror());
        // Some of OpenImageIO's writers report no error when the disk fills
        // up (a truncated file and success): read the file back.
        auto in = OIIO::ImageInput::open(temporary);
        std::vector<float> check(image.pixels.size());
        const bool complete = in && in->read_image(0, 0, 0, image.channels(), OIIO::TypeDesc::FLOAT, check.data());
        if (in) in->close();
        if (!complete) throw std::runtime_error(path + ": cannot write image: the file was cut short (is the disk full?)");
    }

    std::vector<float> colorMap(const std::vector<float>& values, int width, int height,
                                const std::string& map) override {
        OIIO::ImageBuf source(OIIO::ImageSpec(width, height, 1, OIIO::TypeDesc::FLOAT), const_cast<float*>(values.data()));
        const OIIO::ImageBuf colored = OIIO::ImageBufAlgo::color_map(source, 0, map);
        if (colored.has_error()) throw std::runtime_error("cannot apply the colour map: " + colored.geterror());
        std::vector<float> rgb(size_t(width) * height * 3);
        colored.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, rgb.data());
        return rgb;
    }

    std::string drawText(float* rgb, int width, int height, int x, int y, const std::string& text, int size,
                         const std::string& font) override {
        OIIO::ImageBuf buffer(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT), rgb);
        const float white[3] = {1, 1, 1};
        if (OIIO::ImageBufAlgo::render_text(buffer, x, y, text, size, font, white)) return "";
        const std::string message = buffer.geterror();
        return message.empty() ? "no reason given" : message;
    }

    std::unique_ptr<TextureImage> openTexture(const std::string& path) override {
        TextureSystem::TextureHandle* handle = textureSystem().get_texture_handle(OIIO::ustring(path));
        if (!handle) throw std::runtime_error(path + ": cannot open the texture: " + textureSystem().geterror());
        return std::make_unique<OpenImageIoTexture>(handle);
    }
};

}  // namespace

}  // namespace isotrace

extern "C" __attribute__((visibility("default"))) isotrace::OpenImageIoLibrary* isotraceOpenImageIoLibrary() {
    static isotrace::Library library;
    return &library;
}
