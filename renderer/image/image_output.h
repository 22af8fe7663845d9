// Writing renders: scene-referred linear EXR with metadata, and an sRGB PNG
// preview. Files appear only when complete (written under a temporary name
// in the same folder, then renamed).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "renderer/image/film.h"
#include "renderer/image/exr_file.h"
#include "renderer/image/partial_files.h"

namespace isotrace {

/// Writes R, G, B and the AOV channels: EXR (float or half) through
/// OpenEXR, any other format OpenImageIO knows from the extension. Throws
/// std::runtime_error naming the path on failure.
void writeImage(const std::string& path, const Image& image, const ImageMetadata& metadata, bool half);
/// A render's EXR (the channels of writeImage), compressed and written band
/// by band while the render goes on: pass rowsFinished() as
/// RenderOptions::rowsFinished, then call finish(). Until then the file has
/// a temporary name in the same folder, removed if the render fails or is
/// interrupted; finish() renames it into place. `lateStrings` are
/// attributes known only after the render (its time), each with the width
/// reserved for its value.
class RenderExrWriter {
public:
    RenderExrWriter(std::string path, ImageMetadata metadata, bool half,
                    std::vector<std::pair<std::string, size_t>> lateStrings = {});
    ~RenderExrWriter();
    /// Rows [previous end, end) of `image` are final. Throws std::runtime_error naming the path.
    void rowsFinished(const Image& image, int end);
    /// Writes any rows not handed over yet and the late values, then the file.
    void finish(const Image& image, const std::vector<std::pair<std::string, std::string>>& lateValues = {});

private:
    std::string errorNamingTheOutput(const std::string& message) const;
    std::string path_, temporary_;
    ImageMetadata metadata_;
    bool half_;
    std::vector<std::pair<std::string, size_t>> late_;
    std::unique_ptr<PartialFile> guard_;  // removes the temporary file on SIGINT or SIGTERM
    std::unique_ptr<ExrRowWriter> writer_;
    std::vector<ChannelPlane> planes_;
};

/// 8-bit sRGB preview, exposure in stops: PNG through libpng (other
/// extensions through OpenImageIO).
void writePreviewPng(const std::string& path, const Image& image, double exposure);
/// The preview's name next to an output: out.exr -> out.png.
std::string previewPathFor(const std::string& exrPath);
/// Checks an output path before any work, so nothing is half done: throws
/// InputError naming `path` when its folder does not exist, when something
/// that is not a regular file (a folder, a device) has its name, or when it
/// is one of `inputs` (by file identity, however it is spelt).
void checkOutputPath(const std::string& path, const std::vector<std::string>& inputs = {});
/// Reads an image as RGB float (first three channels), with its window in
/// the full frame; throws std::runtime_error naming the path. `metadata`,
/// when given, receives the string attributes.
Image readImage(const std::string& path, ImageMetadata* metadata = nullptr);

}  // namespace isotrace
