#include "renderer/image/film.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "geometry/errors.h"

using namespace isotrace;

TEST(AovLayout, ChannelsFollowTheFixedOrderWhateverWasAsked) {
    const AovLayout layout({"steps", "albedo", "id", "albedo"});
    EXPECT_EQ(layout.channels(), (std::vector<std::string>{"albedo.R", "albedo.G", "albedo.B", "id", "steps"}));
    EXPECT_EQ(layout.offset(Aov::Albedo), 0);
    EXPECT_EQ(layout.offset(Aov::Id), 3);
    EXPECT_EQ(layout.offset(Aov::Steps), 4);
    EXPECT_FALSE(layout.has(Aov::Normal));
    EXPECT_FALSE(layout.has(Aov::Depth));
    const AovLayout all(AovLayout::names());
    EXPECT_EQ(all.channelCount(), size_t(AovLayout::kMaxChannels));
    EXPECT_EQ(all.offset(Aov::Normal), 3);
    EXPECT_EQ(all.offset(Aov::Depth), 6);
    EXPECT_THROW(AovLayout({"albedo", "colour"}), std::invalid_argument);
}

namespace {

// A window of a 3x4 frame whose pixel values are their frame coordinates.
FilmTile tileOf(const std::string& file, int y0, int y1, const std::string& seed = "1") {
    FilmTile t;
    t.file = file;
    t.image.width = 3;
    t.image.height = y1 - y0;
    t.image.y = y0;
    t.image.fullWidth = 3;
    t.image.fullHeight = 4;
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < 3; ++x) t.image.rgb.insert(t.image.rgb.end(), {float(x), float(y), 7.0f});
    t.metadata.strings = {{"isotrace:seed", seed},
                          {"isotrace:spp", "4"},
                          {"isotrace:version", "1.0.0"},
                          {"isotrace:numeric_mode", "double"},
                          {"isotrace:instruction_set", "avx2"}};
    return t;
}

}  // namespace

TEST(MergeTiles, ReassemblesBandsExactly) {
    ImageMetadata metadata;
    const Image full = mergeTiles({tileOf("b.exr", 2, 4), tileOf("a.exr", 0, 2)}, &metadata);
    ASSERT_EQ(full.width, 3);
    ASSERT_EQ(full.height, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 3; ++x) {
            EXPECT_EQ(full.pixel(x, y)[0], float(x));
            EXPECT_EQ(full.pixel(x, y)[1], float(y));
        }
    EXPECT_EQ(metadataValue(metadata, "isotrace:spp"), "4");
}

TEST(MergeTiles, RefusesGapsOverlapsAndForeignTiles) {
    auto message = [](const std::vector<FilmTile>& tiles) {
        try {
            mergeTiles(tiles);
        } catch (const geometry::InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message({tileOf("a.exr", 0, 2)}).find("pixel (0, 2) is missing"), std::string::npos);
    EXPECT_NE(message({tileOf("a.exr", 0, 3), tileOf("b.exr", 2, 4)}).find("b.exr: overlaps a.exr at pixel (0, 2)"),
              std::string::npos);
    EXPECT_NE(message({tileOf("a.exr", 0, 2), tileOf("b.exr", 2, 4, "2")}).find("tiles of different renders"),
              std::string::npos);
    FilmTile plain = tileOf("c.exr", 2, 4);
    plain.metadata.strings.clear();
    EXPECT_NE(message({tileOf("a.exr", 0, 2), plain}).find("c.exr: not an isotrace render"), std::string::npos);
}

// Tiles rendered by another version or in another numeric mode may differ by
// more than noise: refused, naming both values. The instruction set only
// reorders sums: tiles of AVX2 and AVX-512 nodes merge.
TEST(MergeTiles, RefusesTilesOfAnotherVersionOrNumericMode) {
    auto withValue = [](FilmTile tile, const std::string& key, const std::string& value) {
        for (auto& [name, v] : tile.metadata.strings)
            if (name == key) v = value;
        return tile;
    };
    auto message = [](const std::vector<FilmTile>& tiles) {
        try {
            mergeTiles(tiles);
        } catch (const geometry::InputError& e) {
            return std::string(e.what());
        }
        return std::string("merged");
    };
    const FilmTile top = tileOf("top.exr", 0, 2), bottom = tileOf("bottom.exr", 2, 4);
    EXPECT_EQ(message({top, bottom}), "merged");
    EXPECT_EQ(message({top, withValue(bottom, "isotrace:instruction_set", "avx512")}), "merged");
    const std::string version = message({top, withValue(bottom, "isotrace:version", "1.1.0")});
    EXPECT_NE(version.find("bottom.exr: isotrace:version is \"1.1.0\" but top.exr has \"1.0.0\""), std::string::npos)
        << version;
    const std::string mode = message({top, withValue(bottom, "isotrace:numeric_mode", "single")});
    EXPECT_NE(mode.find("isotrace:numeric_mode is \"single\" but top.exr has \"double\""), std::string::npos) << mode;
}

TEST(FilmMemory, GrowsWithThePixelCount) {
    EXPECT_DOUBLE_EQ(estimateFilmBytes(200, 100), 2.0 * estimateFilmBytes(100, 100));
    EXPECT_GT(estimateFilmBytes(1, 1), 3 * 8);  // at least the double sums
}
