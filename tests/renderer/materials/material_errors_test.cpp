// Bad material and texture values get errors naming the file, the JSON path
// and what is wrong.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <fstream>

#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::sceneError;
using isotrace::testing::TemporaryFolder;

namespace {

std::string withMaterial(const std::string& material) {
    return R"({"camera": {"from": [0, 0, 5], "to": [0, 0, 0]},
               "materials": {"m": )" + material + R"(},
               "fields": {"ball": {"type": "sphere", "radius": 1}},
               "objects": [{"field": "ball", "material": "m"}]})";
}

void expectError(const TemporaryFolder& folder, const std::string& material, const std::string& where,
                 const std::string& what) {
    isotrace::testing::expectNamedError(sceneError(folder, withMaterial(material)), where, what);
}

}  // namespace

TEST(MaterialErrors, ValidMaterialsLoad) {
    TemporaryFolder folder;
    for (const char* m : {R"({"type": "conductor", "metal": "gold", "roughness": 0.2})",
                          R"({"type": "conductor", "eta": [0.2, 0.4, 1.3], "k": [3, 2, 1]})",
                          R"({"type": "conductor", "reflectance": [0.9, 0.8, 0.5]})",
                          R"({"type": "dielectric", "ior": 1.33, "roughness": 0.1})",
                          R"({"type": "dielectric", "thin": true})",
                          R"({"type": "plastic", "albedo": {"type": "checker", "colors": [[1, 0, 0], [0, 0, 1]]}})"})
        EXPECT_EQ(sceneError(folder, withMaterial(m)), "") << m;
}

TEST(MaterialErrors, RoughnessOutsideZeroToOne) {
    TemporaryFolder folder;
    expectError(folder, R"({"type": "conductor", "roughness": 1.5})", "/materials/m/roughness", "must lie in [0, 1]");
    expectError(folder, R"({"type": "dielectric", "roughness": -0.1})", "/materials/m/roughness", "must lie in [0, 1]");
    expectError(folder, R"({"type": "plastic", "roughness": {"type": "checker", "colors": [0.2, 3]}})",
                "/materials/m/roughness", "must lie in [0, 1]");
}

TEST(MaterialErrors, IndexOfRefraction) {
    TemporaryFolder folder;
    expectError(folder, R"({"type": "dielectric", "ior": 0})", "/materials/m/ior", "must be positive");
    expectError(folder, R"({"type": "dielectric", "ior": -1.5})", "/materials/m/ior", "must be positive");
    expectError(folder, R"({"type": "plastic", "ior": 1})", "/materials/m/ior", "above 1");
    expectError(folder, R"({"type": "dielectric", "ior": 1e6})", "/materials/m/ior", "at most 10");
    expectError(folder, R"({"type": "conductor", "eta": [0, 1, 1], "k": [1, 1, 1]})", "/materials/m/eta", "positive");
    expectError(folder, R"({"type": "conductor", "eta": [1, 1, 1]})", "/materials/m", "go together");
    expectError(folder, R"({"type": "conductor", "metal": "gold", "reflectance": [1, 1, 1]})", "/materials/m",
                "give one of");
    expectError(folder, R"({"type": "conductor", "metal": "gould"})", "/materials/m/metal", "did you mean \"gold\"");
    expectError(folder, R"({"type": "dielectric", "thin": true, "roughness": 0.2})", "/materials/m/roughness",
                "thin dielectric is smooth");
}

TEST(MaterialErrors, ColoursAboveOneOrNegative) {
    TemporaryFolder folder;
    expectError(folder, R"({"type": "diffuse", "albedo": [1.2, 0.5, 0.5]})", "/materials/m/albedo", "creates energy");
    expectError(folder, R"({"type": "plastic", "albedo": [-0.2, 0.5, 0.5]})", "/materials/m/albedo", "negative");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "noise", "colors": [0, 2]}})", "/materials/m/albedo",
                "creates energy");
    expectError(folder, R"({"type": "diffuse", "albedo": "red"})", "/materials/m/albedo", "expected an array of 3 numbers");
}

TEST(MaterialErrors, Textures) {
    TemporaryFolder folder;
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "marble"}})", "/materials/m/albedo/type",
                "unknown");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "checker", "scale": 0}})",
                "/materials/m/albedo/scale", "greater than 0");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "checker", "colour": [0, 1]}})",
                "/materials/m/albedo/colour", "unknown key");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "noise", "octaves": 0}})",
                "/materials/m/albedo/octaves", "between 1 and 16");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "noise", "colors": [0.1]}})",
                "/materials/m/albedo/colors", "two values");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "image", "file": "x.exr", "sharpness": 100}})",
                "/materials/m/albedo/sharpness", "at most 64");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "ball", "quantity": "gauss", "ramp": [[0, 0], [1, 1]]}})",
                "/materials/m/albedo/quantity", "mean_curvature");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "ball", "ramp": [[0, 0]]}})",
                "/materials/m/albedo/ramp", "at least two stops");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "image", "file": "missing.exr"}})",
                "/materials/m/albedo/file", "no such file");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "bal", "ramp": [[0, 0], [1, 1]]}})",
                "/materials/m/albedo/field", "unknown field \"bal\" (did you mean \"ball\"?)");
    expectError(folder, R"({"type": "diffuse", "albedo": {"type": "field_ramp", "field": "ball", "ramp": [[1, 0], [0, 1]]}})",
                "/materials/m/albedo/ramp/1/0", "must increase");
    // A corrupt image, an image of two channels, an RGB image for a roughness.
    {
        std::ofstream(folder.file("corrupt.exr")) << "not an image";
        expectError(folder, R"({"type": "diffuse", "albedo": {"type": "image", "file": "corrupt.exr"}})",
                    "/materials/m/albedo/file", "cannot read");
    }
    {
        OIIO::ImageBuf two(OIIO::ImageSpec(4, 4, 2, OIIO::TypeDesc::FLOAT));
        ASSERT_TRUE(two.write(folder.file("two.exr")));
        expectError(folder, R"({"type": "diffuse", "albedo": {"type": "image", "file": "two.exr"}})",
                    "/materials/m/albedo/file", "has 2 channels");
        OIIO::ImageBuf rgb(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT));
        ASSERT_TRUE(rgb.write(folder.file("rgb.exr")));
        expectError(folder, R"({"type": "conductor", "roughness": {"type": "image", "file": "rgb.exr"}})",
                    "/materials/m/roughness", "must have one channel; the image \"rgb.exr\" has 3");
        OIIO::ImageBuf nan(OIIO::ImageSpec(2, 2, 1, OIIO::TypeDesc::FLOAT));
        const float values[4] = {0.1f, NAN, 0.2f, 0.3f};
        nan.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, values);
        ASSERT_TRUE(nan.write(folder.file("nan.exr")));
        expectError(folder, R"({"type": "conductor", "roughness": {"type": "image", "file": "nan.exr"}})",
                    "/materials/m/roughness/file", "NaN");
    }
}
