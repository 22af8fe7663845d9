#include "renderer/render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

#include "renderer/image/image_comparison.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::loadSceneText;
using isotrace::testing::TemporaryFolder;

namespace {
const char* kMixedScene = R"({
  "camera": {"from": [0, 1, 4], "to": [0, 0, 0], "fov": 45, "aperture": 0.05},
  "film": {"width": 48, "height": 40, "spp": 8},
  "integrator": {"type": "path", "max_depth": 6},
  "materials": {"clay": {"type": "diffuse", "albedo": [0.7, 0.6, 0.5]}, "mirror": {"type": "mirror"}},
  "fields": {"blob": {"type": "blobby", "blobs": [{"center": [-0.3, 0, 0], "radius": 1}, {"center": [0.4, 0.2, 0], "radius": 0.8}]}},
  "objects": [{"field": "blob", "material": "clay"},
              {"vertices": [-3, -0.8, -3, 3, -0.8, -3, 3, -0.8, 3, -3, -0.8, 3], "indices": [0, 2, 1, 0, 3, 2], "material": "mirror"}],
  "lights": [{"type": "quad", "corner": [-0.5, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": [5, 5, 5]},
             {"type": "point", "position": [2, 3, 2], "intensity": [5, 5, 5]},
             {"type": "environment", "radiance": [0.2, 0.2, 0.25]}]})";
}

TEST(Render, SameBitsOnOneAndTwoThreads) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, kMixedScene);
    const Image one = render(*scene, {.threads = 1, .seed = 11, .quiet = true});
    const Image two = render(*scene, {.threads = 2, .seed = 11, .quiet = true});
    ASSERT_EQ(one.rgb.size(), two.rgb.size());
    EXPECT_EQ(std::memcmp(one.rgb.data(), two.rgb.data(), one.rgb.size() * sizeof(float)), 0);
    // And the seed matters: otherwise the comparison above proves nothing.
    const Image other = render(*scene, {.threads = 2, .seed = 12, .quiet = true});
    EXPECT_NE(std::memcmp(one.rgb.data(), other.rgb.data(), one.rgb.size() * sizeof(float)), 0);
}

TEST(Render, IndependentSamplerIsDeterministicToo) {
    TemporaryFolder folder;
    std::string text = kMixedScene;
    text.replace(text.find("\"spp\": 8"), 8, "\"spp\": 8, \"sampler\": \"independent\"");
    auto scene = loadSceneText(folder, text);
    const Image a = render(*scene, {.threads = 1, .seed = 2, .quiet = true});
    const Image b = render(*scene, {.threads = 2, .seed = 2, .quiet = true});
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
}

// The same sphere sphere traced and as a fine marching-cubes mesh (128
// cells across: faces within ~3e-5 of the surface, normals from the
// gradient) renders alike. With the Whitted integrator and the same seed the
// only differences come from geometry: silhouette pixels (about 1% of the
// image) and shading on faces tilted by under a degree. So: mean absolute
// difference under 0.5% of the mean, and under 2% of pixels off by 10%.
TEST(Render, ImplicitAndFineMeshOfOneSphereAgree) {
    TemporaryFolder folder;
    const std::string scene = R"({"camera": {"from": [0, 1, 4], "to": [0, 0, 0], "fov": 40},
      "film": {"width": 64, "height": 48, "spp": 16},
      "integrator": {"type": "whitted", "max_depth": 2},
      "materials": {"clay": {"type": "diffuse", "albedo": [0.7, 0.6, 0.5]}},
      "fields": {"ball": {"type": "sphere", "radius": 1}},
      "objects": [{"field": "ball", "material": "clay", "resolution": 128},
                  {"vertices": [-5, -1, -5, 5, -1, -5, 5, -1, 5, -5, -1, 5], "indices": [0, 2, 1, 0, 3, 2], "material": "clay"}],
      "lights": [{"type": "point", "position": [2, 4, 3], "intensity": [20, 20, 20]},
                 {"type": "environment", "radiance": [0.2, 0.2, 0.2]}]})";
    SceneOverrides asMesh;
    asMesh.fieldMode = SceneOverrides::FieldMode::Mesh;
    const Image implicit = render(*loadSceneText(folder, scene), {.threads = 2, .seed = 4, .quiet = true});
    const Image mesh = render(*loadSceneText(folder, scene, asMesh), {.threads = 2, .seed = 4, .quiet = true});
    const ImageDifference d = compareImages(mesh, implicit, 0.1);
    EXPECT_LT(d.meanAbsolute, 0.005 * d.referenceMean);
    EXPECT_LT(d.fractionOver, 0.02);
}

// AOVs of the first hit: the centre pixel sees the sphere (object 0) at
// depth 3, with a normal towards the camera, the clay's albedo and some
// sphere-tracing steps; a pixel that sees only the floor mesh has none.
TEST(Render, ArbitraryOutputVariablesDescribeTheFirstHit) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, R"({"camera": {"from": [0, 0, 4], "to": [0, 0, 0], "fov": 40},
      "film": {"width": 33, "height": 33, "spp": 4, "filter": {"type": "box", "radius": 0.5}},
      "materials": {"clay": {"type": "diffuse", "albedo": [0.7, 0.6, 0.5]}, "grey": {"type": "diffuse"}},
      "fields": {"ball": {"type": "sphere", "radius": 1}},
      "objects": [{"field": "ball", "material": "clay"},
                  {"vertices": [-9, -1.2, -9, 9, -1.2, -9, 9, -1.2, 9, -9, -1.2, 9], "indices": [0, 2, 1, 0, 3, 2], "material": "grey"}],
      "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})");
    RenderOptions options{.threads = 2, .seed = 1, .quiet = true};
    options.aovs = {"albedo", "normal", "depth", "id", "steps"};
    const Image image = render(*scene, options);
    ASSERT_EQ(image.extraChannels.size(), 9u);
    auto channel = [&](const std::string& name) {
        return int(std::find(image.extraChannels.begin(), image.extraChannels.end(), name) - image.extraChannels.begin());
    };
    const float* centre = image.extraPixel(16, 16);
    EXPECT_NEAR(centre[channel("Z")], 3.0, 0.01);
    EXPECT_EQ(centre[channel("id")], 0.0f);
    EXPECT_NEAR(centre[channel("albedo.R")], 0.7, 1e-6);
    EXPECT_GT(centre[channel("N.Z")], 0.99);
    EXPECT_GT(centre[channel("steps")], 0.0f);
    const float* floor = image.extraPixel(16, 32);
    EXPECT_EQ(floor[channel("id")], 1.0f);
    EXPECT_EQ(floor[channel("steps")], 0.0f);
    // Colour is the same bits with or without AOVs.
    const Image plain = render(*scene, {.threads = 2, .seed = 1, .quiet = true});
    EXPECT_EQ(std::memcmp(plain.rgb.data(), image.rgb.data(), plain.rgb.size() * sizeof(float)), 0);
}

// Finished rows are handed over in order, one call at a time, each band
// final when handed over (its pixels are the finished image's), ending
// with the last row; a crop's rows are counted inside the window.
TEST(Render, FinishedRowsAreHandedOverInOrderAndFinal) {
    TemporaryFolder folder;
    std::string text = kMixedScene;
    text.replace(text.find("\"height\": 40"), 12, "\"height\": 150");
    auto scene = loadSceneText(folder, text);
    for (const PixelWindow crop : {PixelWindow{}, PixelWindow{5, 3, 40, 120}}) {
        std::vector<int> ends;
        std::vector<float> handedOver;
        std::atomic<int> inside{0};
        int overlapping = 0;
        RenderOptions options{.threads = 2, .crop = crop, .seed = 3, .quiet = true};
        options.rowsFinished = [&](const Image& image, int end) {
            if (++inside != 1) ++overlapping;
            const int first = ends.empty() ? 0 : ends.back();
            handedOver.insert(handedOver.end(), image.rgb.begin() + ptrdiff_t(3) * image.width * first,
                              image.rgb.begin() + ptrdiff_t(3) * image.width * end);
            ends.push_back(end);
            --inside;
        };
        const Image image = render(*scene, options);
        EXPECT_EQ(overlapping, 0);
        ASSERT_FALSE(ends.empty());
        EXPECT_TRUE(std::is_sorted(ends.begin(), ends.end()) && std::adjacent_find(ends.begin(), ends.end()) == ends.end());
        EXPECT_EQ(ends.back(), image.height);
        ASSERT_EQ(handedOver.size(), image.rgb.size());
        EXPECT_EQ(std::memcmp(handedOver.data(), image.rgb.data(), image.rgb.size() * sizeof(float)), 0);
    }
}

// Every tile is taken exactly once; a band's tiles all come before the next
// band's, column by column, each column from the top; the last band may be
// shorter.
TEST(Render, TilesAreTakenOnceBandByBandColumnByColumn) {
    for (const auto& [tilesX, tilesY] : {std::pair{40, 30}, std::pair{1, 1}, std::pair{3, kTileBandRows + 1},
                                        std::pair{7, 2 * kTileBandRows}, std::pair{1, 2 * kTileBandRows - 1}}) {
        std::vector<int> takenAt(size_t(tilesX) * tilesY, -1);
        int previousRow = 0, previousColumn = 0;
        for (int order = 0; order < tilesX * tilesY; ++order) {
            const int tile = tileInRenderOrder(order, tilesX, tilesY);
            ASSERT_GE(tile, 0);
            ASSERT_LT(tile, tilesX * tilesY);
            EXPECT_EQ(takenAt[tile], -1) << "tile " << tile << " taken twice";
            takenAt[tile] = order;
            const int row = tile / tilesX, column = tile % tilesX;
            if (order > 0) {
                const int band = row / kTileBandRows, previousBand = previousRow / kTileBandRows;
                EXPECT_GE(band, previousBand);
                if (band == previousBand) {
                    // The next tile down the column, or the top of the next column.
                    const bool down = column == previousColumn && row == previousRow + 1;
                    const bool nextColumn = column == previousColumn + 1 && row == band * kTileBandRows;
                    EXPECT_TRUE(down || nextColumn) << "order " << order << " " << tilesX << "x" << tilesY;
                } else {
                    EXPECT_EQ(row, band * kTileBandRows);
                    EXPECT_EQ(column, 0);
                }
            }
            previousRow = row;
            previousColumn = column;
        }
    }
}

// A writer's failure stops the render and reaches the caller.
TEST(Render, AFailureToTakeRowsStopsTheRender) {
    TemporaryFolder folder;
    auto scene = loadSceneText(folder, kMixedScene);
    RenderOptions options{.threads = 2, .seed = 3, .quiet = true};
    options.rowsFinished = [](const Image&, int) { throw std::runtime_error("disk full"); };
    EXPECT_THROW(render(*scene, options), std::runtime_error);
}
