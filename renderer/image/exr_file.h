// OpenEXR files read and written directly through OpenEXR, so that renders,
// tiles and merges never load OpenImageIO and its hundreds of libraries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "renderer/image/image_file.h"

namespace isotrace {

/// Writes every channel as float or half (`format` Byte is not an EXR
/// format), the window inside its full frame (data and display windows),
/// ZIP compressed, with the string attributes. Throws std::runtime_error
/// with OpenEXR's message.
void writeExr(const std::string& path, const ImageFile& image, SampleFormat format);
/// The same with the samples at `pixels` (image.channels() floats per pixel,
/// row-major) instead of in image.pixels: a render's colour buffer goes to
/// the file without a copy.
void writeExr(const std::string& path, const ImageFile& image, const float* pixels, SampleFormat format);

/// One channel of an image in memory: the sample of window pixel (x, y) is
/// at first[(y * width + x) * stride].
struct ChannelPlane {
    const float* first = nullptr;
    size_t stride = 1;
};

/// An EXR made band by band while its rows are still being made. A render
/// hands over each band of rows as its last tile finishes, and the band is
/// compressed and written on that thread while the others render on:
/// compression no longer waits for the last pixel. Attributes known only at
/// the end (a render's time) get a reserved width and are filled in by
/// finish(). The file is incomplete until then: write it under a temporary
/// name. Not thread-safe: callers hand over bands one at a time, in order.
class ExrRowWriter {
public:
    /// Creates `path`. `layout` gives the window, frame, channel names and
    /// string attributes (its pixels are not used); `lateStrings` names
    /// further string attributes with the width reserved for each value.
    /// Throws std::runtime_error naming the path.
    ExrRowWriter(const std::string& path, const ImageFile& layout, SampleFormat format,
                 std::vector<std::pair<std::string, size_t>> lateStrings);
    ~ExrRowWriter();
    /// Compresses and writes window rows [rowsWritten(), end) from `planes`,
    /// one per channel of the layout in its order. Those rows must be final.
    void writeRows(const std::vector<ChannelPlane>& planes, int end);
    int rowsWritten() const { return rowsWritten_; }
    /// Completes and closes the file once every row is written, with the
    /// late values (each at most its reserved width; shorter ones keep
    /// trailing spaces). Throws std::logic_error on misuse,
    /// std::runtime_error when the file cannot be written.
    void finish(const std::vector<std::pair<std::string, std::string>>& lateValues);

private:
    class FileStream;  // the file, keeping its header's bytes
    struct Encoder;    // OpenEXR's file over that stream
    ImageFile layout_;
    SampleFormat format_;
    std::vector<std::pair<std::string, size_t>> late_;
    std::unique_ptr<Encoder> encoder_;
    std::vector<uint16_t> halves_;  // half samples, when the file stores half
    int rowsWritten_ = 0;
};

/// Reads every channel as float: R, G, B, A first, then the AOV channels
/// in the order renders write them (a file keeps its channels sorted by
/// name), then the rest by name. Throws std::runtime_error with OpenEXR's
/// message; refuses sizes no image of this renderer has before allocating.
ImageFile readExr(const std::string& path, bool withPixels = true);

}  // namespace isotrace
