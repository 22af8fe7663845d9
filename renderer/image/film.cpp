#include "renderer/image/film.h"

#include <algorithm>
#include <stdexcept>

#include "geometry/errors.h"

namespace isotrace {

using geometry::InputError;

std::string metadataValue(const ImageMetadata& metadata, const std::string& name) {
    for (const auto& [key, value] : metadata.strings)
        if (key == name) return value;
    return "";
}

const std::vector<std::string>& AovLayout::names() {
    static const std::vector<std::string> names{"albedo", "normal", "depth", "id", "steps"};
    return names;
}

AovLayout::AovLayout(const std::vector<std::string>& requested) {
    for (const std::string& name : requested)
        if (std::find(names().begin(), names().end(), name) == names().end())
            throw std::invalid_argument("unknown AOV \"" + name + "\"");
    auto wants = [&](const char* name) { return std::count(requested.begin(), requested.end(), name) > 0; };
    auto add = [&](Aov aov, std::initializer_list<const char*> channels) {
        offset_[int(aov)] = int(channels_.size());
        channels_.insert(channels_.end(), channels.begin(), channels.end());
    };
    if (wants("albedo")) add(Aov::Albedo, {"albedo.R", "albedo.G", "albedo.B"});
    if (wants("normal")) add(Aov::Normal, {"N.X", "N.Y", "N.Z"});
    if (wants("depth")) add(Aov::Depth, {"Z"});
    if (wants("id")) add(Aov::Id, {"id"});
    if (wants("steps")) add(Aov::Steps, {"steps"});
}

double estimateFilmBytes(int width, int height) {
    // Double RGB sums, float RGB output, 8-bit preview.
    return double(width) * double(height) * (3 * 8 + 3 * 4 + 3);
}

Image mergeTiles(const std::vector<FilmTile>& tiles, ImageMetadata* metadata) {
    if (tiles.empty()) throw std::invalid_argument("no tiles to merge");
    const FilmTile& first = tiles.front();
    Image full;
    full.width = full.fullWidth = first.image.fullWidth;
    full.height = full.fullHeight = first.image.fullHeight;
    full.rgb.assign(size_t(full.width) * full.height * 3, 0.0f);
    full.extraChannels = first.image.extraChannels;
    full.extra.assign(size_t(full.width) * full.height * full.extraChannels.size(), 0.0f);
    std::vector<int> owner(size_t(full.width) * full.height, -1);
    // Tiles of another version or numeric mode may differ by more than
    // noise; the instruction set only reorders sums, and may differ.
    const char* mustMatch[] = {"isotrace:version",    "isotrace:numeric_mode", "isotrace:scene_hash",
                               "isotrace:seed",       "isotrace:spp",          "isotrace:integrator"};
    for (size_t t = 0; t < tiles.size(); ++t) {
        const std::string& path = tiles[t].file;
        const Image& tile = tiles[t].image;
        if (metadataValue(tiles[t].metadata, "isotrace:seed").empty())
            throw InputError(path, "", "not an isotrace render (no isotrace metadata)");
        if (t > 0) {
            if (tile.fullWidth != full.width || tile.fullHeight != full.height)
                throw InputError(path, "", "frame size " + std::to_string(tile.fullWidth) + "x" +
                                               std::to_string(tile.fullHeight) + " differs from " + first.file + "'s " +
                                               std::to_string(full.width) + "x" + std::to_string(full.height));
            if (tile.extraChannels != full.extraChannels)
                throw InputError(path, "", "its channels differ from " + first.file + "'s");
            for (const char* key : mustMatch)
                if (metadataValue(tiles[t].metadata, key) != metadataValue(first.metadata, key))
                    throw InputError(path, "", std::string(key) + " is \"" + metadataValue(tiles[t].metadata, key) +
                                                   "\" but " + first.file + " has \"" +
                                                   metadataValue(first.metadata, key) + "\": tiles of different renders");
        }
        for (int y = 0; y < tile.height; ++y)
            for (int x = 0; x < tile.width; ++x) {
                const int fx = tile.x + x, fy = tile.y + y;
                if (fx < 0 || fy < 0 || fx >= full.width || fy >= full.height)
                    throw InputError(path, "", "its window lies outside the frame");
                int& o = owner[size_t(fy) * full.width + fx];
                if (o >= 0)
                    throw InputError(path, "", "overlaps " + tiles[o].file + " at pixel (" + std::to_string(fx) + ", " +
                                                   std::to_string(fy) + ")");
                o = int(t);
                std::copy_n(tile.pixel(x, y), 3, full.pixel(fx, fy));
                if (!full.extraChannels.empty())
                    std::copy_n(tile.extraPixel(x, y), full.extraChannels.size(), full.extraPixel(fx, fy));
            }
    }
    for (size_t p = 0; p < owner.size(); ++p)
        if (owner[p] < 0)
            throw InputError(first.file, "", "the tiles do not cover the frame: pixel (" + std::to_string(p % full.width) +
                                                 ", " + std::to_string(p / full.width) + ") is missing");
    if (metadata) *metadata = first.metadata;
    return full;
}

}  // namespace isotrace
