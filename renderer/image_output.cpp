#include "renderer/image_output.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

#include "geometry/input_error.h"
#include "renderer/partial_files.h"

namespace isotrace {

namespace {

std::string temporaryPathFor(const std::string& path) {
    // Same folder (rename stays atomic), same extension (OIIO picks the format by it).
    const std::filesystem::path p(path);
    return (p.parent_path() / ("." + p.stem().string() + ".partial-" + std::to_string(getpid()) + p.extension().string()))
        .string();
}

void writeBuffer(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc memoryType, const void* pixels) {
    const std::string temporary = temporaryPathFor(path);
    const PartialFile guard(temporary);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error(path + ": cannot write this image format (" + OIIO::geterror() + ")");
    bool ok = out->open(temporary, spec) && out->write_image(memoryType, pixels) && out->close();
    if (!ok) {
        const std::string message = out->geterror();
        std::filesystem::remove(temporary);
        throw std::runtime_error(path + ": cannot write image: " + message);
    }
    // OpenImageIO's PNG writer reports no error when the disk fills up (a
    // truncated file and success): read such files back before they count.
    if (std::filesystem::path(path).extension() != ".exr") {
        auto in = OIIO::ImageInput::open(temporary);
        std::vector<unsigned char> check(spec.image_bytes());
        if (!in || !in->read_image(0, 0, 0, spec.nchannels, spec.format, check.data())) {
            if (in) in->close();
            std::filesystem::remove(temporary);
            throw std::runtime_error(path + ": cannot write image: the file was cut short (is the disk full?)");
        }
        in->close();
    }
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary);
        throw std::runtime_error(path + ": cannot move the finished image into place: " + ec.message());
    }
}

}  // namespace

void writeImage(const std::string& path, const Image& image, const ImageMetadata& metadata, bool half) {
    const int channels = 3 + int(image.extraChannels.size());
    OIIO::ImageSpec spec(image.width, image.height, channels, half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B"};
    spec.channelnames.insert(spec.channelnames.end(), image.extraChannels.begin(), image.extraChannels.end());
    // A window of a larger frame keeps its place (EXR data window inside
    // the display window), which is what `isotrace merge` reads back.
    spec.x = image.x;
    spec.y = image.y;
    spec.full_x = 0;
    spec.full_y = 0;
    spec.full_width = image.fullWidth > 0 ? image.fullWidth : image.width;
    spec.full_height = image.fullHeight > 0 ? image.fullHeight : image.height;
    for (const auto& [name, value] : metadata.strings) spec.attribute(name, value);
    if (image.extraChannels.empty()) {
        writeBuffer(path, spec, OIIO::TypeDesc::FLOAT, image.rgb.data());  // OIIO converts to half if asked
        return;
    }
    // Interleave colour and AOV channels per pixel.
    const size_t pixels = size_t(image.width) * image.height, extra = image.extraChannels.size();
    std::vector<float> all(pixels * channels);
    for (size_t p = 0; p < pixels; ++p) {
        std::copy_n(&image.rgb[3 * p], 3, &all[p * channels]);
        std::copy_n(&image.extra[extra * p], extra, &all[p * channels + 3]);
    }
    writeBuffer(path, spec, OIIO::TypeDesc::FLOAT, all.data());
}

void writePreviewPng(const std::string& path, const Image& image, double exposure) {
    const double scale = std::exp2(exposure);
    std::vector<unsigned char> bytes(image.rgb.size());
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        double v = std::clamp(double(image.rgb[i]) * scale, 0.0, 1.0);
        if (std::isnan(v)) v = 0.0;
        // sRGB transfer function.
        v = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
        bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0));
    }
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    writeBuffer(path, spec, OIIO::TypeDesc::UINT8, bytes.data());
}

void checkOutputPath(const std::string& path, const std::vector<std::string>& inputs) {
    const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
    if (!std::filesystem::is_directory(parent))
        throw geometry::InputError(path, "", "the output folder " + parent.string() + " does not exist");
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status)) return;
    if (!std::filesystem::is_regular_file(status))
        throw geometry::InputError(path, "", "exists and is not a regular file; refusing to replace it");
    for (const std::string& input : inputs)
        if (std::filesystem::equivalent(path, input, ec))
            throw geometry::InputError(path, "", "is also an input (" + input + "); refusing to overwrite it");
}

std::string previewPathFor(const std::string& exrPath) {
    std::filesystem::path p(exrPath);
    p.replace_extension(".png");
    return p.string();
}

Image readImage(const std::string& path, ImageMetadata* metadata) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error(path + ": cannot read image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    Image image;
    image.width = spec.width;
    image.height = spec.height;
    image.x = spec.x;
    image.y = spec.y;
    image.fullWidth = spec.full_width;
    image.fullHeight = spec.full_height;
    std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
        throw std::runtime_error(path + ": cannot read image: " + in->geterror());
    if (metadata)
        for (const OIIO::ParamValue& p : spec.extra_attribs)
            if (p.type() == OIIO::TypeDesc::STRING) metadata->strings.emplace_back(p.name().string(), p.get_string());
    image.rgb.resize(size_t(spec.width) * spec.height * 3);
    for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
        for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] = all[p * spec.nchannels + std::min(c, spec.nchannels - 1)];
    // Channels past the first three (AOVs) come along, so merge keeps them.
    for (int c = 3; c < spec.nchannels; ++c) image.extraChannels.push_back(spec.channelnames[c]);
    const size_t extra = image.extraChannels.size();
    image.extra.resize(size_t(spec.width) * spec.height * extra);
    for (size_t p = 0; p < size_t(spec.width) * spec.height; ++p)
        for (size_t c = 0; c < extra; ++c) image.extra[p * extra + c] = all[p * spec.nchannels + 3 + c];
    return image;
}

}  // namespace isotrace
