// The film: what a render produces and how it is laid out. Images of a frame
// or of a window of it (crops and tiles), the film settings of a scene, the
// named AOV channels, the memory a frame needs, and the merging of tiles.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "renderer/sampling/pixel_filter.h"
#include "renderer/sampling/sampler.h"

namespace isotrace {

/// Pixels of a frame, or of a window of it (a crop or tile): pixel (0, 0)
/// of the image is pixel (x, y) of the full frame.
struct Image {
    int width = 0, height = 0;
    int x = 0, y = 0;                      ///< the window's place in the full frame
    int fullWidth = 0, fullHeight = 0;     ///< the full frame (0: same as width, height)
    std::vector<float> rgb;  ///< row-major, three floats per pixel
    /// Further channels (AOVs), `extraChannels.size()` floats per pixel.
    std::vector<std::string> extraChannels;
    std::vector<float> extra;
    float* pixel(int x, int y) { return &rgb[3 * (size_t(y) * width + x)]; }
    float* extraPixel(int x, int y) { return &extra[extraChannels.size() * (size_t(y) * width + x)]; }
    const float* extraPixel(int x, int y) const { return &extra[extraChannels.size() * (size_t(y) * width + x)]; }
    const float* pixel(int x, int y) const { return &rgb[3 * (size_t(y) * width + x)]; }
};

/// A window of the frame: columns [x0, x1) and rows [y0, y1).
struct PixelWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
};

/// The "film" of a scene file.
struct FilmSettings {
    int width = 640;
    int height = 480;
    int samplesPerPixel = 16;
    PixelFilter filter;
    SamplerType sampler = SamplerType::Sobol;
};

/// String attributes stored with an image (EXR header entries).
struct ImageMetadata {
    std::vector<std::pair<std::string, std::string>> strings;  ///< name, value
};
/// The value of a metadata entry, or "" when absent.
std::string metadataValue(const ImageMetadata& metadata, const std::string& name);

/// The arbitrary output variables a render can add, in their channel order.
/// Each is averaged over a pixel's samples, except `id` (the first sample's).
enum class Aov { Albedo, Normal, Depth, Id, Steps };

/// Where each requested AOV sits among a pixel's extra channels.
class AovLayout {
public:
    /// `names` as given by the user ("albedo", "normal", "depth", "id",
    /// "steps"); channels follow the fixed order of Aov, whatever the order
    /// or repetition of the names. Throws std::invalid_argument for others.
    explicit AovLayout(const std::vector<std::string>& names = {});

    static const std::vector<std::string>& names();
    bool has(Aov aov) const { return offset_[int(aov)] >= 0; }
    /// First channel of `aov` (which must be present).
    int offset(Aov aov) const { return offset_[int(aov)]; }
    const std::vector<std::string>& channels() const { return channels_; }
    size_t channelCount() const { return channels_.size(); }
    /// The most channels any layout has (fixed-size per-pixel sums).
    static constexpr int kMaxChannels = 9;

private:
    int offset_[5] = {-1, -1, -1, -1, -1};
    std::vector<std::string> channels_;
};

/// Bytes a render of this size needs (film sums, output and preview).
double estimateFilmBytes(int width, int height);

/// One tile of a frame to merge, with the file it came from (for errors).
struct FilmTile {
    std::string file;
    Image image;
    ImageMetadata metadata;
};

/// Reassembles windows of one frame. They must come from the same scene,
/// seed, sample count and integrator and frame size, and cover the frame
/// exactly once; otherwise InputError names the tile at fault. The result
/// keeps the first tile's metadata.
Image mergeTiles(const std::vector<FilmTile>& tiles, ImageMetadata* metadata = nullptr);

}  // namespace isotrace
