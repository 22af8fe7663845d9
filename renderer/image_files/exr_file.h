// OpenEXR files read and written directly through OpenEXR, so that renders,
// tiles and merges never load OpenImageIO and its hundreds of libraries.
#pragma once

#include <string>

#include "renderer/image_files/image_file.h"

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

/// Reads every channel as float: R, G, B, A first, then the AOV channels
/// in the order renders write them (a file keeps its channels sorted by
/// name), then the rest by name. Throws std::runtime_error with OpenEXR's
/// message; refuses sizes no image of this renderer has before allocating.
ImageFile readExr(const std::string& path, bool withPixels = true);

}  // namespace isotrace
