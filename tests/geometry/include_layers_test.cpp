// The layers of the two libraries (README.md, "Layers"): includes only run
// downward, and folders of one layer do not include each other.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace {

namespace fs = std::filesystem;

// The layer of a source file by its path from the project root, or -1 when
// it belongs to no library.
int layerOf(const std::string& path) {
    auto in = [&](const char* folder) { return path.rfind(folder, 0) == 0; };
    if (in("geometry/fields/") || in("geometry/variational/")) return 1;
    // Point-set implicits blend the variational solver's interpolants.
    if (in("geometry/pointsets/")) return 2;
    if (in("geometry/field_program.")) return 3;
    if (in("geometry/tracing/") || in("geometry/meshing/")) return 4;
    if (in("geometry/particles/")) return 5;
    if (in("geometry/description/")) return 6;
    if (in("geometry/")) return 0;
    if (in("renderer/commands/")) return 11;
    if (in("renderer/materials/") || in("renderer/textures/") || in("renderer/lights/") || in("renderer/integrators/"))
        return 10;
    if (in("renderer/image/")) return 8;
    if (in("renderer/platform/") || in("renderer/sampling/")) return 7;
    if (in("renderer/")) return 9;
    return -1;
}

std::string folderOf(const std::string& path) { return fs::path(path).parent_path().string(); }

}  // namespace

TEST(IncludeLayers, IncludesOnlyRunDownward) {
    const fs::path root = ISOTRACE_SOURCE_DIR;
    const std::regex include(R"re(^\s*#\s*include\s+"([^"]+)")re");
    int checked = 0;
    std::vector<std::string> violations;
    for (const char* library : {"geometry", "renderer"}) {
        for (const auto& entry : fs::recursive_directory_iterator(root / library)) {
            const std::string ext = entry.path().extension().string();
            if (ext != ".h" && ext != ".cpp") continue;
            const std::string file = fs::relative(entry.path(), root).generic_string();
            std::ifstream in(entry.path());
            std::string line;
            while (std::getline(in, line)) {
                std::smatch m;
                if (!std::regex_search(line, m, include)) continue;
                const std::string target = m[1];
                ++checked;
                if (!fs::exists(root / target)) {
                    violations.push_back(file + " includes \"" + target + "\", not a path from the project root");
                    continue;
                }
                const int from = layerOf(file), to = layerOf(target);
                const bool peerFolders = from == to && folderOf(file) != folderOf(target);
                if (to > from || peerFolders)
                    violations.push_back(file + " (layer " + std::to_string(from) + ") includes " + target + " (layer " +
                                         std::to_string(to) + ")");
            }
        }
    }
    EXPECT_GT(checked, 200);  // the walk found the sources
    for (const std::string& v : violations) ADD_FAILURE() << v;
}

TEST(IncludeLayers, LayersOfKnownFiles) {
    EXPECT_LT(layerOf("geometry/interval.h"), layerOf("geometry/fields/sphere.h"));
    EXPECT_LT(layerOf("geometry/variational/variational_field.h"), layerOf("geometry/field_program.h"));
    EXPECT_LT(layerOf("geometry/field_program.h"), layerOf("geometry/tracing/implicit_surface.h"));
    EXPECT_LT(layerOf("geometry/meshing/polygonizer.h"), layerOf("geometry/description/field_parser.h"));
    EXPECT_LT(layerOf("geometry/description/field_parser.h"), layerOf("renderer/scene.h"));
    EXPECT_LT(layerOf("renderer/material.h"), layerOf("renderer/materials/diffuse.cpp"));
    EXPECT_LT(layerOf("renderer/sampling/sampler.h"), layerOf("renderer/image/film.h"));
    EXPECT_LT(layerOf("renderer/image/film.h"), layerOf("renderer/scene.h"));
    EXPECT_LT(layerOf("renderer/scene_builder.h"), layerOf("renderer/lights/area_light.h"));
    EXPECT_EQ(layerOf("renderer/platform/version.h"), layerOf("renderer/sampling/sampler.h"));
    EXPECT_LT(layerOf("renderer/integrators/path_integrator.cpp"), layerOf("renderer/commands/command.h"));
}
