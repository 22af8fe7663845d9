#include "renderer/image/png_file.h"
#include "geometry/errors.h"

#include <png.h>

#include <stdexcept>

namespace isotrace {

void writePng(const std::string& path, const unsigned char* rgb, int width, int height) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(width);
    image.height = png_uint_32(height);
    image.format = PNG_FORMAT_RGB;
    // A preview: zlib's fast setting writes a 640x480 render in a third of
    // the time for a file about 15% larger.
    image.flags = PNG_IMAGE_FLAG_FAST;
    // png_image_write_to_file checks fflush, ferror and fclose: short
    // writes fail here rather than leave a truncated file behind.
    if (!png_image_write_to_file(&image, path.c_str(), 0, rgb, 0, nullptr)) {
        const std::string message = image.message;
        png_image_free(&image);
        throw geometry::IoError(path, "cannot write image: " + message);
    }
}

}  // namespace isotrace
