// An image file's contents as every reader here returns them: all channels
// as float, interleaved, with the file's window, channel names and string
// attributes. EXR goes through OpenEXR (exr_file.h), the preview PNG
// through libpng (png_file.h), every other format through OpenImageIO,
// loaded only when such a file is met (openimageio_library.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace isotrace {

struct ImageFile {
    int width = 0, height = 0;
    int x = 0, y = 0;                   ///< the data window's place in the full frame
    int fullWidth = 0, fullHeight = 0;  ///< the full (display) frame
    /// R, G, B (and A) first when the file has them; grey files have one
    /// channel (Y first when present).
    std::vector<std::string> channelNames;
    bool floatingPoint = true;  ///< linear HDR data (EXR, HDR, float TIFF) rather than display-encoded values
    std::vector<std::pair<std::string, std::string>> strings;  ///< string attributes: name, value
    std::vector<float> pixels;  ///< row-major, channelNames.size() floats per pixel

    int channels() const { return int(channelNames.size()); }
};

/// How a writer stores the samples.
enum class SampleFormat { Float, Half, Byte };

/// Reads `path` by its extension (any case): .exr through OpenEXR, others
/// through OpenImageIO. `withPixels` false reads the header only. Throws
/// std::runtime_error naming the path.
ImageFile readImageFile(const std::string& path, bool withPixels = true);

}  // namespace isotrace
