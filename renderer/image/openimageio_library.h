// What only OpenImageIO provides here (formats other than EXR and the
// preview PNG, MIP-mapped texture lookups, colour maps, text), behind an
// interface whose implementation lives in a module of its own
// (isotrace_openimageio.so) and is loaded on first use. OpenImageIO's
// Debian build maps some 250 shared libraries; a process that never reads
// such a file never pays for them (`isotrace --version` in milliseconds).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "renderer/image/image_file.h"

namespace isotrace {

/// A texture opened in OpenImageIO's shared texture system: MIP-mapped on
/// first use, tiles cached across the process. Lookups are thread safe.
class TextureImage {
public:
    virtual ~TextureImage() = default;
    /// Bilinear MIP-mapped lookup at (s, t), wrapping periodically, over a
    /// square footprint `width` wide in texture space; writes `channels`
    /// floats to `out`.
    virtual void lookup(float s, float t, float width, int channels, float* out) const = 0;
};

class OpenImageIoLibrary {
public:
    virtual ~OpenImageIoLibrary() = default;
    /// Throws std::runtime_error naming the path.
    virtual ImageFile read(const std::string& path, bool withPixels) = 0;
    /// Writes `image` in the format `path`'s extension names, to
    /// `temporary` (the caller renames it). Throws std::runtime_error.
    virtual void write(const std::string& path, const std::string& temporary, const ImageFile& image,
                       SampleFormat format) = 0;
    /// One value per pixel mapped to display-encoded RGB by the named map
    /// ("magma", ...). Throws std::runtime_error.
    virtual std::vector<float> colorMap(const std::vector<float>& values, int width, int height,
                                        const std::string& map) = 0;
    /// Draws white text into linear RGB (3 floats per pixel) with its
    /// baseline's left end at (x, y); returns "" or the reason it could not.
    virtual std::string drawText(float* rgb, int width, int height, int x, int y, const std::string& text, int size,
                                 const std::string& font) = 0;
    /// Throws std::runtime_error naming the path.
    virtual std::unique_ptr<TextureImage> openTexture(const std::string& path) = 0;
};

/// The library, loaded on the first call: from $ISOTRACE_OPENIMAGEIO_MODULE
/// when set (only there), else next to the executable, in the folder
/// above it (build trees: tests/, bench/), or in ../lib/isotrace (an
/// installed tree). Throws std::runtime_error saying where it looked.
OpenImageIoLibrary& openImageIo();

}  // namespace isotrace

/// The module's one entry point (C linkage, so dlsym finds it by name).
extern "C" isotrace::OpenImageIoLibrary* isotraceOpenImageIoLibrary();
