// Textures against what they are defined to be: the checker's parity, the
// noise's range and determinism, image lookups of known texels (linear EXR
// and sRGB PNG), and field ramps by value and by mean curvature.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <cmath>

#include "geometry/description/field_parser.h"
#include "renderer/texture.h"
#include "support/plugin_catalog.h"
#include "support/temporary_files.h"

using namespace isotrace;
using namespace isotrace::testing;

namespace {

std::shared_ptr<const Texture> makeTexture(const geometry::Json& description, const MaterialContext& context = {}) {
    geometry::JsonObjectReader r(description, "", "texture");
    auto texture = textureRegistry().factoryFor(r)(r, context);
    r.finish();
    return texture;
}

ShadingPoint at(const Vec3& p, const Vec3& n = Vec3(0, 0, 1)) {
    ShadingPoint s;
    s.position = s.objectPosition = p;
    s.geometricNormal = s.shadingNormal = s.objectNormal = n;
    return s;
}

}  // namespace

TEST(Textures, CheckerAlternatesByCellParity) {
    const auto checker = makeTexture({{"type", "checker"}, {"scale", 0.5}, {"colors", {0.1, 0.9}}});
    EXPECT_EQ(checker->channels(), 1);
    EXPECT_DOUBLE_EQ(checker->evaluate(at({0.1, 0.1, 0.1}))[0], 0.1);
    EXPECT_DOUBLE_EQ(checker->evaluate(at({0.6, 0.1, 0.1}))[0], 0.9);
    EXPECT_DOUBLE_EQ(checker->evaluate(at({0.6, 0.6, 0.1}))[0], 0.1);
    EXPECT_DOUBLE_EQ(checker->evaluate(at({-0.1, 0.1, 0.1}))[0], 0.9) << "cells continue across zero";
    const auto colour = makeTexture({{"type", "checker"}, {"colors", {{1, 0, 0}, {0, 0, 1}}}});
    EXPECT_EQ(colour->channels(), 3);
}

TEST(Textures, NoiseStaysInRangeVariesAndRepeatsBySeed) {
    const auto a = makeTexture({{"type", "noise"}, {"scale", 0.2}, {"colors", {0.2, 0.7}}, {"seed", 1}});
    const auto b = makeTexture({{"type", "noise"}, {"scale", 0.2}, {"colors", {0.2, 0.7}}, {"seed", 2}});
    double lowest = 1, highest = 0, differences = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p(0.013 * i, 0.7 * std::sin(0.1 * i), 0.031 * i);
        const double v = a->evaluate(at(p))[0];
        lowest = std::min(lowest, v);
        highest = std::max(highest, v);
        EXPECT_EQ(v, a->evaluate(at(p))[0]);
        differences += std::abs(v - b->evaluate(at(p))[0]);
    }
    EXPECT_GE(lowest, 0.2);
    EXPECT_LE(highest, 0.7);
    EXPECT_GT(highest - lowest, 0.2) << "noise that barely varies";
    EXPECT_GT(differences / 1000, 0.02) << "the seed changes the pattern";
}

// A 2 x 1 image (red | blue) on the plane facing +z: texel centres read
// back exactly with a point footprint, and an sRGB PNG is decoded to linear.
TEST(Textures, ImageTexelsReadBackThroughTheTriplanarProjection) {
    TemporaryFolder folder;
    OIIO::ImageBuf image(OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::FLOAT));
    const float texels[6] = {0.8f, 0.1f, 0.1f, 0.1f, 0.2f, 0.9f};
    image.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, texels);
    ASSERT_TRUE(image.write(folder.file("two.exr")));
    MaterialContext context;
    context.directory = folder.path();
    const auto texture = makeTexture({{"type", "image"}, {"file", "two.exr"}, {"scale", 1.0}}, context);
    EXPECT_EQ(texture->channels(), 3);
    EXPECT_NEAR(texture->maximum()[2], 0.9, 1e-7);
    // s = x, t = 1 - y: the centre of texel 0 is x = 0.25, of texel 1 x = 0.75.
    const RGB left = texture->evaluate(at({0.25, 0.5, 0}));
    const RGB right = texture->evaluate(at({0.75, 0.5, 0}));
    EXPECT_NEAR(left[0], 0.8, 1e-5);
    EXPECT_NEAR(left[2], 0.1, 1e-5);
    EXPECT_NEAR(right[0], 0.1, 1e-5);
    EXPECT_NEAR(right[2], 0.9, 1e-5);
    // A large footprint averages the two.
    ShadingPoint wide = at({0.25, 0.5, 0});
    wide.footprint = 4.0;
    EXPECT_NEAR(texture->evaluate(wide)[0], 0.45, 0.02);

    OIIO::ImageBuf grey(OIIO::ImageSpec(2, 2, 1, OIIO::TypeDesc::UINT8));
    const unsigned char bytes[4] = {128, 128, 128, 128};
    grey.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, bytes);
    ASSERT_TRUE(grey.write(folder.file("grey.png")));
    const auto png = makeTexture({{"type", "image"}, {"file", "grey.png"}}, context);
    EXPECT_EQ(png->channels(), 1);
    const double v = 128 / 255.0;
    EXPECT_NEAR(png->evaluate(at({0.3, 0.3, 0.3}, Vec3(1, 1, 1).normalized()))[1], std::pow((v + 0.055) / 1.055, 2.4), 1e-4);
}

// The same image placed by texture coordinates: v runs up the image (as in
// OBJ files and Blender), a point without them falls back to the projection,
// and "color_space": "linear" reads a PNG's bytes as data.
TEST(Textures, ImageTexelsReadBackByTextureCoordinates) {
    TemporaryFolder folder;
    OIIO::ImageBuf image(OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT));
    // Rows from the top: (red, green), (blue, white).
    const float texels[12] = {0.8f, 0.1f, 0.1f, 0.1f, 0.7f, 0.1f, 0.1f, 0.1f, 0.9f, 1.0f, 1.0f, 1.0f};
    image.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, texels);
    ASSERT_TRUE(image.write(folder.file("four.exr")));
    MaterialContext context;
    context.directory = folder.path();
    const auto texture = makeTexture({{"type", "image"}, {"file", "four.exr"}, {"mapping", "uv"}}, context);
    auto withUv = [](double u, double v) {
        ShadingPoint s = at({5.0, 5.0, 0.0});  // far from where the projection would read
        s.uv = Eigen::Vector2d(u, v);
        s.hasUv = true;
        return s;
    };
    EXPECT_NEAR(texture->evaluate(withUv(0.25, 0.75))[0], 0.8, 1e-5);  // top left: red
    EXPECT_NEAR(texture->evaluate(withUv(0.75, 0.75))[1], 0.7, 1e-5);  // top right: green
    EXPECT_NEAR(texture->evaluate(withUv(0.25, 0.25))[2], 0.9, 1e-5);  // bottom left: blue
    EXPECT_NEAR(texture->evaluate(withUv(1.75, 0.25))[0], 1.0, 1e-5);  // repeats: bottom right, white
    ShadingPoint wide = withUv(0.25, 0.75);
    wide.uvFootprint = 4.0;
    EXPECT_NEAR(texture->evaluate(wide)[0], (0.8 + 0.1 + 0.1 + 1.0) / 4, 0.02);  // the mean of the four
    const RGB projected = makeTexture({{"type", "image"}, {"file", "four.exr"}}, context)->evaluate(at({5.25, 5.75, 0}));
    const RGB fallback = texture->evaluate(at({5.25, 5.75, 0}));
    EXPECT_TRUE((fallback == projected).all()) << fallback.transpose() << " vs " << projected.transpose();

    OIIO::ImageBuf grey(OIIO::ImageSpec(2, 2, 1, OIIO::TypeDesc::UINT8));
    const unsigned char bytes[4] = {128, 128, 128, 128};
    grey.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::UINT8, bytes);
    ASSERT_TRUE(grey.write(folder.file("rough.png")));
    const auto data = makeTexture({{"type", "image"}, {"file", "rough.png"}, {"mapping", "uv"}, {"color_space", "linear"}}, context);
    EXPECT_NEAR(data->evaluate(withUv(0.5, 0.5))[0], 128 / 255.0, 1e-4);
    EXPECT_NEAR(data->maximum()[0], 128 / 255.0, 1e-6);
}

TEST(Textures, FieldRampsByValueAndByMeanCurvature) {
    geometry::FieldLibrary fields(geometry::Json{{"ball", {{"type", "sphere"}, {"radius", 2.0}}}}, "/fields", "test");
    MaterialContext context;
    context.fields = &fields;
    const auto byValue = makeTexture(
        {{"type", "field_ramp"}, {"field", "ball"}, {"ramp", {{-2, {0, 0, 0}}, {2, {1, 0.5, 0.25}}}}}, context);
    // At distance 3 from the centre the sphere's field is 1: three quarters along the ramp.
    const RGB v = byValue->evaluate(at({0, 3, 0}));
    EXPECT_NEAR(v[0], 0.75, 1e-12);
    EXPECT_NEAR(v[2], 0.1875, 1e-12);
    EXPECT_EQ(byValue->evaluate(at({0, 9, 0}))[0], 1.0) << "constant beyond the last stop";
    const auto byCurvature = makeTexture(
        {{"type", "field_ramp"}, {"field", "ball"}, {"quantity", "mean_curvature"}, {"ramp", {{0, 0}, {1, 1}}}}, context);
    // A sphere of radius 2 has mean curvature 1/2 everywhere on it.
    for (const Vec3& p : {Vec3(2, 0, 0), Vec3(0, -2, 0), Vec3(1.2, 1.6, 0)})
        EXPECT_NEAR(byCurvature->evaluate(at(p))[0], 0.5, 1e-4) << p.transpose();
}

TEST(PluginCatalog, CoversEveryRegisteredTextureType) {
    EXPECT_EQ(missingFrom(textureCatalog(), textureRegistry().names()), std::vector<std::string>{})
        << "add the new texture type to tests/support/plugin_catalog.h";
}

namespace {

class EveryTexture : public ::testing::TestWithParam<PluginEntry> {};

}  // namespace

// Every texture keeps within the bounds it declares (materials validate
// their parameters by them), gives the same value twice at a point, and
// varies over a region a few times its scale.
TEST_P(EveryTexture, StaysWithinItsBoundsRepeatsAndVaries) {
    TemporaryFolder folder;
    OIIO::ImageBuf image(OIIO::ImageSpec(3, 2, 3, OIIO::TypeDesc::FLOAT));
    const float texels[18] = {0.8f, 0.1f, 0.1f, 0.1f, 0.2f, 0.9f, 0.3f, 0.3f, 0.3f,
                              0.0f, 0.5f, 1.0f, 0.6f, 0.6f, 0.1f, 0.2f, 0.9f, 0.4f};
    image.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, texels);
    ASSERT_TRUE(image.write(folder.file("catalog.exr")));
    geometry::FieldLibrary fields(geometry::Json{{"ball", {{"type", "sphere"}, {"radius", 2.0}}}}, "/fields", "test");
    MaterialContext context;
    context.directory = folder.path();
    context.fields = &fields;
    const auto texture = makeTexture(GetParam().description, context);

    ASSERT_TRUE(texture->channels() == 1 || texture->channels() == 3);
    const RGB lowest = texture->minimum(), highest = texture->maximum();
    ASSERT_TRUE((lowest <= highest).all());
    RGB seenLowest = RGB::Constant(1e300), seenHighest = RGB::Constant(-1e300);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p(2.0 * std::sin(0.37 * i), 2.0 * std::cos(0.11 * i), 2.0 * std::sin(0.23 * i + 1));
        const Vec3 n = Vec3(std::cos(0.7 * i), std::sin(0.3 * i), 0.5).normalized();
        const RGB v = texture->evaluate(at(p, n));
        ASSERT_TRUE(v.isFinite().all()) << p.transpose();
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(v[c], lowest[c] - 1e-12) << "channel " << c << " at " << p.transpose();
            EXPECT_LE(v[c], highest[c] + 1e-12) << "channel " << c << " at " << p.transpose();
        }
        EXPECT_TRUE((v == texture->evaluate(at(p, n))).all()) << p.transpose();
        seenLowest = seenLowest.min(v);
        seenHighest = seenHighest.max(v);
    }
    EXPECT_GT((seenHighest - seenLowest).maxCoeff(), 0.05) << "a texture that does not vary";
}

INSTANTIATE_TEST_SUITE_P(Catalog, EveryTexture, ::testing::ValuesIn(textureCatalog()),
                         [](const auto& info) { return info.param.name; });
