// The 8-bit sRGB preview written directly through libpng, so that a render
// and its preview never load OpenImageIO.
#pragma once

#include <string>

namespace isotrace {

/// Writes `width` x `height` pixels of 8-bit RGB (row-major, 3 bytes per
/// pixel). Throws std::runtime_error with libpng's message; a write that
/// fails part way (a full disk) is an error, not a short file.
void writePng(const std::string& path, const unsigned char* rgb, int width, int height);

}  // namespace isotrace
