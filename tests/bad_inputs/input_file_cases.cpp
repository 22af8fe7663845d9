// Broken files handed to commands directly: meshes and point sets to
// `fit`, images to `compare` and `merge`, and environment maps and
// textures whose pixels are not radiance (NaN, negative, two channels).
#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {
namespace {

/// The bytes of a small float image, every texel `fill` but one `odd`.
std::string imageBytes(const std::string& extension, int width, int height, int channels, float fill, float odd) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("isotrace-corpus-image-" + std::to_string(::getpid()) + extension);
    std::vector<float> pixels(size_t(width) * height * channels, fill);
    pixels[channels * (width + 1)] = odd;
    {
        auto out = OIIO::ImageOutput::create(path.string());
        OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
        if (!out || !out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()))
            return "";
        out->close();
    }
    std::ifstream in(path, std::ios::binary);
    std::string bytes(std::istreambuf_iterator<char>(in), {});
    std::filesystem::remove(path);
    return bytes;
}

BadInputCase withFile(const std::string& name, const std::string& file, const std::string& content,
                      const std::string& arguments, std::vector<std::string> mentions,
                      std::vector<std::string> setup = {}) {
    return makeCase(name, arguments, std::move(mentions), std::move(setup), {{file, content}});
}

}  // namespace

std::vector<BadInputCase> inputFileCases() {
    std::vector<BadInputCase> cases;
    auto add = [&](BadInputCase c) { cases.push_back(std::move(c)); };
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const std::vector<std::string> images = {"isotrace render small.json -o a.exr --quiet --no-preview"};

    // Meshes to fit.
    const std::string offHeader = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    const std::pair<const char*, std::string> offFiles[] = {
        {"empty", ""},
        {"magic_only", "OFF\n"},
        {"index_out_of_range", offHeader + "3 0 2 99\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"negative_index", offHeader + "3 0 2 -1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"truncated", offHeader + "3 0 2 1\n3 0\n"},
        {"nan_vertex", "OFF\n4 4 0\n0 0 0\nnan 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"header_billion", "OFF\n1000000000 1000000000 0\n"},
        {"all_degenerate", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n"},
        {"flat_square", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"},
        {"binary_garbage", std::string("\x7f" "ELF\x02\x01\x01\0\0\0\0\0", 12)},
    };
    for (const auto& [what, content] : offFiles)
        add(withFile(std::string("fit_off_") + what, "m.off", content, "fit m.off -o out.json", {"m.off"}));
    add(withFile("fit_obj_index_beyond", "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "fit m.obj -o out.json", {"m.obj"}));
    add(withFile("fit_ply_header_billion", "m.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n0 0 0\n",
                 "fit m.ply -o out.json", {"m.ply"}));
    add(withFile("fit_ply_header_unended", "m.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar int vertex_indices\nend_head\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                 "fit m.ply -o out.json", {"m.ply", "end_header"}));

    // Point sets to fit.
    const std::pair<const char*, std::string> pointFiles[] = {
        {"empty", ""},
        {"comments_only", "# nothing here\n# at all\n"},
        {"nan", "0 0 0 1 0 0\nnan 1 0 1 0 0\n0 0 1 0 0 1\n1 1 1 1 0 0\n"},
        {"zero_normal", "0 0 0 1 0 0\n1 0 0 0 0 0\n0 0 1 0 0 1\n1 1 1 1 0 0\n"},
        {"three_columns", "0 0 0\n1 0 0\n0 1 0\n"},
        {"one_point", "0 0 0 0 0 1\n"},
        {"coplanar", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n1 1 0 0 0 1\n2 2 0 0 0 1\n"},
        {"coincident", "1 1 1 0 0 1\n1 1 1 0 1 0\n1 1 1 1 0 0\n"},
        {"huge_coordinate", "0 0 0 1 0 0\n1e300 1 0 1 0 0\n0 0 1 0 0 1\n1 1 1 1 0 0\n"},
    };
    for (const auto& [what, content] : pointFiles)
        add(withFile(std::string("fit_points_") + what, "p.xyz", content, "fit p.xyz -o out.json", {"p.xyz"}));

    // Images to compare and merge.
    const std::pair<const char*, std::string> imageFiles[] = {
        {"empty", ""},
        {"text", "this is not an image\n"},
        {"png_signature_only", "\x89PNG\r\n\x1a\n"},
        {"exr_magic_only", "v/1\x01"},
        {"truncated_exr", imageBytes(".exr", 12, 8, 3, 0.5f, 0.5f).substr(0, 120)},
    };
    for (const auto& [what, content] : imageFiles) {
        add(withFile(std::string("compare_test_") + what, "x.exr", content, "compare x.exr a.exr", {"x.exr"}, images));
        add(withFile(std::string("compare_reference_") + what, "x.exr", content, "compare a.exr x.exr", {"x.exr"}, images));
        add(withFile(std::string("merge_") + what, "x.exr", content, "merge x.exr -o out.exr", {"x.exr"}));
    }
    add(withFile("compare_two_channel_image", "x.exr", imageBytes(".exr", 12, 8, 2, 0.5f, 0.5f), "compare x.exr a.exr",
                 {"x.exr"}, images));
    add(withFile("compare_folder_as_image", "x.exr", "", "compare folder a.exr", {"folder"},
                 {images[0], "mkdir folder"}));

    // Environment maps and textures whose pixels cannot be radiance.
    const char* environment = R"({"film": {"width": 8, "height": 6, "spp": 1}, "materials": {"clay": {"type": "diffuse"}},
  "fields": {"ball": {"type": "sphere", "radius": 1}}, "objects": [{"field": "ball", "material": "clay"}],
  "lights": [{"type": "environment", "file": "map.exr"}]})";
    const std::pair<const char*, std::string> maps[] = {
        {"nan_texel", imageBytes(".exr", 16, 8, 3, 0.5f, nan)},
        {"infinite_texel", imageBytes(".exr", 16, 8, 3, 0.5f, inf)},
        {"negative_texel", imageBytes(".exr", 16, 8, 3, 0.5f, -1.0f)},
        {"square", imageBytes(".exr", 8, 8, 3, 0.5f, 0.5f)},
        {"two_channels", imageBytes(".exr", 16, 8, 2, 0.5f, 0.5f)},
    };
    for (const auto& [what, content] : maps) {
        BadInputCase c = withFile(std::string("environment_map_") + what, "map.exr", content,
                                  "render env.json -o out.exr --quiet", {"map.exr"});
        c.files["env.json"] = environment;
        add(std::move(c));
    }
    const char* textured = R"({"film": {"width": 8, "height": 6, "spp": 1},
  "materials": {"clay": {"type": "diffuse", "albedo": {"type": "image", "file": "map.exr"}}},
  "fields": {"ball": {"type": "sphere", "radius": 1}}, "objects": [{"field": "ball", "material": "clay"}],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
    const std::pair<const char*, std::string> textures[] = {
        {"nan_texel", imageBytes(".exr", 8, 8, 3, 0.5f, nan)},
        {"two_channels", imageBytes(".exr", 8, 8, 2, 0.5f, 0.5f)},
    };
    for (const auto& [what, content] : textures) {
        BadInputCase c = withFile(std::string("texture_") + what, "map.exr", content, "render tex.json -o out.exr --quiet",
                                  {"map.exr"});
        c.files["tex.json"] = textured;
        add(std::move(c));
    }
    return cases;
}

}  // namespace isotrace::testing
