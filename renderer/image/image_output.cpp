#include "renderer/image/image_output.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <unistd.h>

#include "geometry/errors.h"
#include "geometry/mesh_file.h"
#include "renderer/image/exr_file.h"
#include "renderer/image/openimageio_library.h"
#include "renderer/image/png_file.h"
#include "renderer/image/partial_files.h"

namespace isotrace {

namespace {

std::string temporaryPathFor(const std::string& path) {
    // Same folder (rename stays atomic), same extension.
    const std::filesystem::path p(path);
    return (p.parent_path() / ("." + p.stem().string() + ".partial-" + std::to_string(getpid()) + p.extension().string()))
        .string();
}

// The finished temporary file renamed to its place, or removed.
void moveIntoPlace(const std::string& temporary, const std::string& path) {
    std::error_code ec, ignored;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary, ignored);
        throw geometry::IoError(path, "cannot move the finished image into place: " + ec.message());
    }
}

// Messages name the file the user asked for, not the temporary one.
std::string namingTheOutput(std::string message, const std::string& temporary, const std::string& path) {
    for (size_t at = message.find(temporary); at != std::string::npos; at = message.find(temporary, at + path.size()))
        message.replace(at, temporary.size(), path);
    return message;
}

// Files appear only when complete: `write` fills a temporary file in the
// same folder, which is then renamed; on any failure (or a signal, through
// PartialFile) it is removed.
void writeAtomically(const std::string& path, const std::function<void(const std::string& temporary)>& write) {
    const std::string temporary = temporaryPathFor(path);
    const PartialFile guard(temporary);
    try {
        write(temporary);
    } catch (const std::runtime_error& e) {  // a writer's failure (the OpenImageIO module reports plain ones)
        std::filesystem::remove(temporary);
        throw geometry::IoError(namingTheOutput(e.what(), temporary, path));
    } catch (...) {
        std::filesystem::remove(temporary);
        throw;
    }
    moveIntoPlace(temporary, path);
}

bool isExr(const std::string& path) { return geometry::lowercaseExtension(path) == ".exr"; }

void writeImageFile(const std::string& path, const ImageFile& image, SampleFormat format) {
    writeAtomically(path, [&](const std::string& temporary) {
        if (isExr(path)) writeExr(temporary, image, format);
        else openImageIo().write(path, temporary, image, format);
    });
}

}  // namespace

ImageFile readImageFile(const std::string& path, bool withPixels) {
    return isExr(path) ? readExr(path, withPixels) : openImageIo().read(path, withPixels);
}

namespace {

// A render's file without its pixels: window, frame, R, G, B then the AOV
// channels, and the metadata.
ImageFile layoutOf(const Image& image, const ImageMetadata& metadata) {
    ImageFile file;
    file.width = image.width;
    file.height = image.height;
    file.x = image.x;
    file.y = image.y;
    file.fullWidth = image.fullWidth > 0 ? image.fullWidth : image.width;
    file.fullHeight = image.fullHeight > 0 ? image.fullHeight : image.height;
    file.channelNames = {"R", "G", "B"};
    file.channelNames.insert(file.channelNames.end(), image.extraChannels.begin(), image.extraChannels.end());
    file.strings = metadata.strings;
    return file;
}

}  // namespace

void writeImage(const std::string& path, const Image& image, const ImageMetadata& metadata, bool half) {
    ImageFile file = layoutOf(image, metadata);
    const size_t pixels = size_t(image.width) * image.height, extra = image.extraChannels.size();
    const SampleFormat format = half ? SampleFormat::Half : SampleFormat::Float;
    if (extra == 0 && isExr(path)) {
        // The colour buffer is the file's layout already.
        writeAtomically(path, [&](const std::string& temporary) { writeExr(temporary, file, image.rgb.data(), format); });
        return;
    }
    // Interleave colour and AOV channels per pixel.
    const size_t channels = 3 + extra;
    file.pixels.resize(pixels * channels);
    for (size_t p = 0; p < pixels; ++p) {
        // Pointers, not &v[i]: without AOVs `extra` is empty (UBSan).
        std::copy_n(image.rgb.data() + 3 * p, 3, file.pixels.data() + p * channels);
        std::copy_n(image.extra.data() + extra * p, extra, file.pixels.data() + p * channels + 3);
    }
    writeImageFile(path, file, format);
}

namespace {

// The 255 linear values at which the sRGB byte steps up: byte k + 1 from
// decode((k + 0.5) / 255) on. Searching them gives the byte that rounding the
// encoded value gives, without a pow per sample (which took a third of the
// time of writing a 640x480 preview).
const std::array<double, 255>& srgbByteThresholds() {
    static const std::array<double, 255> thresholds = [] {
        std::array<double, 255> t{};
        for (int k = 0; k < 255; ++k) {
            const double e = (k + 0.5) / 255.0;
            t[size_t(k)] = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return thresholds;
}

}  // namespace

void writePreviewPng(const std::string& path, const Image& image, double exposure) {
    const double scale = std::exp2(exposure);
    const std::array<double, 255>& thresholds = srgbByteThresholds();
    std::vector<unsigned char> bytes(image.rgb.size());
    for (size_t i = 0; i < image.rgb.size(); ++i) {
        const double v = double(image.rgb[i]) * scale;
        if (!(v > 0.0)) continue;  // negative and NaN samples are black
        bytes[i] = static_cast<unsigned char>(std::upper_bound(thresholds.begin(), thresholds.end(), v) - thresholds.begin());
    }
    writeAtomically(path, [&](const std::string& temporary) {
        if (geometry::lowercaseExtension(path) == ".png") {
            writePng(temporary, bytes.data(), image.width, image.height);
            return;
        }
        ImageFile file;
        file.width = file.fullWidth = image.width;
        file.height = file.fullHeight = image.height;
        file.channelNames = {"R", "G", "B"};
        file.pixels.assign(bytes.begin(), bytes.end());
        for (float& v : file.pixels) v /= 255.0f;
        openImageIo().write(path, temporary, file, SampleFormat::Byte);
    });
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
    const ImageFile file = readImageFile(path);
    Image image;
    image.width = file.width;
    image.height = file.height;
    image.x = file.x;
    image.y = file.y;
    image.fullWidth = file.fullWidth;
    image.fullHeight = file.fullHeight;
    if (metadata) metadata->strings = file.strings;
    const size_t pixels = size_t(file.width) * file.height, channels = size_t(file.channels());
    // Grey files fill all three colour channels (two channels: grey and alpha).
    image.rgb.resize(pixels * 3);
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < 3; ++c) image.rgb[3 * p + c] = file.pixels[p * channels + (channels >= 3 ? c : 0)];
    // Channels past the first three (AOVs) come along, so merge keeps them.
    for (size_t c = 3; c < channels; ++c) image.extraChannels.push_back(file.channelNames[c]);
    const size_t extra = image.extraChannels.size();
    image.extra.resize(pixels * extra);
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < extra; ++c) image.extra[p * extra + c] = file.pixels[p * channels + 3 + c];
    return image;
}

RenderExrWriter::RenderExrWriter(std::string path, ImageMetadata metadata, bool half,
                                 std::vector<std::pair<std::string, size_t>> lateStrings)
    : path_(std::move(path)), temporary_(temporaryPathFor(path_)), metadata_(std::move(metadata)), half_(half),
      late_(std::move(lateStrings)) {}

RenderExrWriter::~RenderExrWriter() {
    if (!writer_) return;
    writer_.reset();  // closes the unfinished file
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
}

void RenderExrWriter::rowsFinished(const Image& image, int end) {
    try {
        if (!writer_) {
            guard_ = std::make_unique<PartialFile>(temporary_);
            writer_ = std::make_unique<ExrRowWriter>(temporary_, layoutOf(image, metadata_),
                                                     half_ ? SampleFormat::Half : SampleFormat::Float, late_);
            planes_.clear();
            for (size_t c = 0; c < 3; ++c) planes_.push_back({image.rgb.data() + c, 3});
            const size_t extra = image.extraChannels.size();
            for (size_t k = 0; k < extra; ++k) planes_.push_back({image.extra.data() + k, extra});
        }
        writer_->writeRows(planes_, end);
    } catch (const std::runtime_error& e) {
        throw geometry::IoError(errorNamingTheOutput(e.what()));
    }
}

void RenderExrWriter::finish(const Image& image, const std::vector<std::pair<std::string, std::string>>& lateValues) {
    if (!writer_ || writer_->rowsWritten() < image.height) rowsFinished(image, image.height);
    try {
        writer_->finish(lateValues);
    } catch (const std::runtime_error& e) {
        throw geometry::IoError(errorNamingTheOutput(e.what()));
    }
    writer_.reset();
    moveIntoPlace(temporary_, path_);
    guard_.reset();
}

// The user's path in the message, in front when the writer did not name it.
std::string RenderExrWriter::errorNamingTheOutput(const std::string& message) const {
    const std::string named = namingTheOutput(message, temporary_, path_);
    return named.find(path_) == std::string::npos ? path_ + ": " + named : named;
}

}  // namespace isotrace
