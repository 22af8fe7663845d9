// The examples of docs/scene-format.md are scenes isotrace loads: every
// ```json block that is one "key": value fragment joins one scene (a
// section's key at the top, anything else as a field), which must load
// and render. A reference whose examples rot fails here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "geometry/description/json_reader.h"
#include "renderer/render.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::loadSceneText;
using isotrace::testing::TemporaryFolder;

TEST(SceneFormatExamples, EveryExampleLoadsAndRendersAsOneScene) {
    const std::filesystem::path source = ISOTRACE_SOURCE_DIR;
    std::ifstream in(source / "docs" / "scene-format.md");
    ASSERT_TRUE(in) << "docs/scene-format.md";
    std::stringstream text;
    text << in.rdbuf();
    const std::string reference = text.str();

    const std::set<std::string> sections{"camera", "film", "integrator", "materials", "objects", "lights"};
    geometry::Json scene = geometry::Json::object();
    scene["fields"] = geometry::Json::object();
    const std::regex block("```json\\n(\"[^`]*?)```");
    int fragments = 0;
    for (std::sregex_iterator it(reference.begin(), reference.end(), block), end; it != end; ++it) {
        const std::string fragment = (*it)[1];
        geometry::Json parsed;
        ASSERT_NO_THROW(parsed = geometry::Json::parse("{" + fragment + "}")) << fragment;
        for (const auto& [key, value] : parsed.items()) {
            if (!sections.count(key)) scene["fields"][key] = value;
            else if (key == "materials") scene["materials"].update(value);
            else scene[key] = value;
        }
        ++fragments;
    }
    EXPECT_GE(fragments, 8) << "the reference's examples were not found";
    for (const char* key : {"camera", "film", "integrator", "materials", "objects", "lights"})
        EXPECT_TRUE(scene.contains(key)) << "no example of \"" << key << "\"";

    TemporaryFolder folder;
    std::filesystem::create_directories(folder.file("meshes"));
    std::filesystem::copy_file(source / "scenes" / "meshes" / "hand.off", folder.file("meshes/hand.off"));
    std::filesystem::copy_file(source / "tests" / "data" / "oni.pwn", folder.file("kitten.xyz"));
    scene["film"]["width"] = 16;
    scene["film"]["height"] = 12;
    scene["film"]["spp"] = 1;
    std::unique_ptr<Scene> loaded;
    ASSERT_NO_THROW(loaded = loadSceneText(folder, scene.dump())) << scene.dump(2);
    EXPECT_EQ(loaded->objects.size(), scene["objects"].size() + 1) << "the objects, and the quad light's emitter";
    const Image image = render(*loaded, {.threads = 2, .seed = 1, .quiet = true});
    double total = 0.0;
    for (const float v : image.rgb) total += v;
    EXPECT_GT(total, 0.0) << "the example scene renders black";
}
