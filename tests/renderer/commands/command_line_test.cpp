// The isotrace executable as users run it: exit codes, messages and the
// guarantee that bad input leaves no output file behind.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "renderer/image/image_output.h"

#include "support/run_command.h"
#include "support/temporary_files.h"

using isotrace::testing::runIsotrace;
using isotrace::testing::TemporaryFolder;

namespace {

const char* kSmallScene = R"({"camera": {"from": [0, 0, 4], "to": [0, 0, 0], "fov": 40},
  "film": {"width": 16, "height": 12, "spp": 2},
  "materials": {"clay": {"type": "diffuse"}},
  "fields": {"ball": {"type": "sphere", "radius": 1}},
  "objects": [{"field": "ball", "material": "clay"}],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";

std::string readFile(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

size_t filesIn(const std::filesystem::path& folder) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder)) ++n;
    return n;
}

}  // namespace

TEST(CommandLine, HelpAndVersionSucceed) {
    const auto help = runIsotrace("--help");
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.output.find("render"), std::string::npos);
    const auto renderHelp = runIsotrace("render --help");
    EXPECT_EQ(renderHelp.exitCode, 0);
    EXPECT_NE(renderHelp.output.find("--spp"), std::string::npos);
    const auto version = runIsotrace("--version");
    EXPECT_EQ(version.exitCode, 0);
    EXPECT_NE(version.output.find("isotrace 0."), std::string::npos);
}

// ISOTRACE_MAX_ISA caps the vector kernels: --version and every render's
// metadata name the set that runs; a misspelt cap is bad input.
TEST(CommandLine, InstructionSetCapIsHonouredAndChecked) {
    const auto capped = isotrace::testing::runShell("ISOTRACE_MAX_ISA=sse2 " ISOTRACE_EXECUTABLE " --version");
    EXPECT_EQ(capped.exitCode, 0) << capped.output;
    EXPECT_NE(capped.output.find("numeric mode double, sse2 kernels"), std::string::npos) << capped.output;
    TemporaryFolder folder;
    const std::string scene = folder.write("scene.json", kSmallScene);
    const auto render = isotrace::testing::runShell("ISOTRACE_MAX_ISA=sse2 " ISOTRACE_EXECUTABLE " render " + scene +
                                                    " -q --no-preview -o " + folder.file("ball.exr"));
    ASSERT_EQ(render.exitCode, 0) << render.output;
    isotrace::ImageMetadata metadata;
    isotrace::readImage(folder.file("ball.exr"), &metadata);
    EXPECT_EQ(isotrace::metadataValue(metadata, "isotrace:instruction_set"), "sse2");
    EXPECT_EQ(isotrace::metadataValue(metadata, "isotrace:numeric_mode"), "double");
    EXPECT_EQ(isotrace::metadataValue(metadata, "isotrace:version").substr(0, 2), "0.");
    const auto misspelt = isotrace::testing::runShell("ISOTRACE_MAX_ISA=avx3 " ISOTRACE_EXECUTABLE " --version");
    EXPECT_EQ(misspelt.exitCode, 2) << misspelt.output;
    EXPECT_NE(misspelt.output.find("ISOTRACE_MAX_ISA: unknown instruction set \"avx3\""), std::string::npos)
        << misspelt.output;
}

TEST(CommandLine, UsageErrorsExitWith2) {
    EXPECT_EQ(runIsotrace("").exitCode, 2);
    EXPECT_EQ(runIsotrace("render").exitCode, 2);
    EXPECT_EQ(runIsotrace("frobnicate").exitCode, 2);
    EXPECT_EQ(runIsotrace("render x.json --spp 0").exitCode, 2);
    EXPECT_EQ(runIsotrace("render x.json --threads -1").exitCode, 2);
    EXPECT_EQ(runIsotrace("render x.json --aov albedo,bogus").exitCode, 2);
    EXPECT_EQ(runIsotrace("render x.json --crop 0 0 4").exitCode, 2);
    EXPECT_EQ(runIsotrace("compare a.exr b.exr --metric bogus").exitCode, 2);
    EXPECT_EQ(runIsotrace("compare a.exr b.exr --fail-percent 150").exitCode, 2);
}

TEST(CommandLine, RendersAnEXRWithMetadataAndAPngPreview) {
    TemporaryFolder folder;
    const std::string scene = folder.write("ball.json", kSmallScene);
    const auto r = runIsotrace("render " + scene + " -o " + folder.file("out.exr") + " --seed 3 --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ASSERT_TRUE(std::filesystem::exists(folder.file("out.png")));
    auto in = OIIO::ImageInput::open(folder.file("out.exr"));
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.width, 16);
    EXPECT_EQ(spec.height, 12);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_NE(spec.get_string_attribute("Software").find("isotrace"), std::string::npos);
    EXPECT_EQ(spec.get_string_attribute("isotrace:seed"), "3");
    EXPECT_EQ(spec.get_string_attribute("isotrace:spp"), "2");
    EXPECT_FALSE(spec.get_string_attribute("isotrace:camera").empty());
    EXPECT_EQ(filesIn(folder.path()), 3u) << "no temporary files may remain";
}

TEST(CommandLine, HalfFloatOutputAndOverrides) {
    TemporaryFolder folder;
    const std::string scene = folder.write("ball.json", kSmallScene);
    const auto r = runIsotrace("render " + scene + " -o " + folder.file("h.exr") +
                               " --half --width 20 --height 10 --spp 1 --no-preview --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto in = OIIO::ImageInput::open(folder.file("h.exr"));
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::HALF);
    EXPECT_EQ(in->spec().width, 20);
    EXPECT_FALSE(std::filesystem::exists(folder.file("h.png")));
}

// Bad input: a message naming the file and place, exit 2, and no file left.
TEST(CommandLine, BadInputLeavesNoOutput) {
    TemporaryFolder folder;
    struct Case {
        std::string name, scene, expect;
    };
    const std::vector<Case> cases{
        {"malformed", "{\"film\": {", "line 1"},
        {"unknown_key", R"({"objects": [], "flim": {}})", "/objects"},
        {"unknown_material", R"({"materials": {}, "objects": [{"field": "x", "material": "m"}]})", "/objects/0/material"},
        {"bad_field", R"({"materials": {"m": {"type": "diffuse"}}, "fields": {"x": {"type": "sphere", "radius": 0}},
                          "objects": [{"field": "x", "material": "m"}]})", "/fields/x/radius"},
    };
    for (const Case& c : cases) {
        const std::string scene = folder.write(c.name + ".json", c.scene);
        const std::string out = folder.file(c.name + ".exr");
        const auto r = runIsotrace("render " + scene + " -o " + out + " --quiet");
        EXPECT_EQ(r.exitCode, 2) << c.name << ": " << r.output;
        EXPECT_NE(r.output.find(c.name + ".json"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << c.name;
        EXPECT_FALSE(std::filesystem::exists(folder.file(c.name + ".png"))) << c.name;
    }
    EXPECT_EQ(filesIn(folder.path()), cases.size()) << "only the scene files may exist";
}

TEST(CommandLine, MissingSceneAndUnwritableOutput) {
    TemporaryFolder folder;
    const auto missing = runIsotrace("render " + folder.file("none.json") + " -o " + folder.file("o.exr"));
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_NE(missing.output.find("none.json"), std::string::npos);
    const std::string scene = folder.write("ball.json", kSmallScene);
    const auto noFolder = runIsotrace("render " + scene + " -o " + folder.file("no/such/folder/o.exr"));
    EXPECT_EQ(noFolder.exitCode, 2);
    EXPECT_NE(noFolder.output.find("does not exist"), std::string::npos) << noFolder.output;
}

namespace {
const char* kFieldScene = R"({"materials": {"m": {"type": "diffuse"}},
  "fields": {"ring": {"type": "torus", "major": 1, "minor": 0.3},
             "open": {"type": "plane"},
             "nothing": {"type": "intersection", "of": [{"type": "sphere", "radius": 1},
                                                         {"type": "sphere", "center": [5, 0, 0], "radius": 1}]}},
  "objects": [{"field": "ring", "material": "m"}]})";
}  // namespace

TEST(CommandLine, PolygonizeWritesTheMeshAndAReport) {
    TemporaryFolder folder;
    const std::string scene = folder.write("s.json", kFieldScene);
    const auto r = runIsotrace("polygonize " + scene + " --field ring -o " + folder.file("ring.ply") +
                               " --resolution 40 --report");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto report = nlohmann::json::parse(r.output);
    EXPECT_EQ(report["euler_characteristic"], 0);
    EXPECT_EQ(report["watertight"], true);
    EXPECT_EQ(report["manifold"], true);
    EXPECT_GT(report["triangles"].get<int>(), 1000);
    EXPECT_LT(report["max_vertex_distance"].get<double>(), 1e-6);
    EXPECT_TRUE(std::filesystem::exists(folder.file("ring.ply")));
    const auto adaptive = runIsotrace("polygonize " + scene + " --field ring -o " + folder.file("ring.off") +
                                      " --method adaptive --tolerance 0.01 --report");
    ASSERT_EQ(adaptive.exitCode, 0) << adaptive.output;
    const auto a = nlohmann::json::parse(adaptive.output);
    EXPECT_LE(a["max_centroid_distance"].get<double>(), 0.01);
    EXPECT_EQ(a["manifold"], true);
    // The stages' times: each taken, together within the whole.
    const double stages = a["extraction_seconds"].get<double>() + a["refinement_seconds"].get<double>() +
                          a["simplification_seconds"].get<double>();
    for (const char* stage : {"extraction_seconds", "refinement_seconds", "simplification_seconds"})
        EXPECT_GT(a[stage].get<double>(), 0.0) << stage;
    EXPECT_LE(stages, a["seconds"].get<double>());
    EXPECT_EQ(report["refinement_seconds"].get<double>(), 0.0);  // marching cubes refines nothing
}

TEST(CommandLine, PolygonizeBadInput) {
    TemporaryFolder folder;
    const std::string scene = folder.write("s.json", kFieldScene);
    struct Case {
        std::string arguments, expect;
        int exitCode;
    };
    const std::vector<Case> cases{
        {"--field ring -o " + folder.file("a.ply") + " --resolution 0", "resolution", 2},
        {"--field ring -o " + folder.file("b.ply") + " --resolution -3", "resolution", 2},
        {"--field ring -o " + folder.file("c.ply") + " --resolution 200000", "GiB", 2},
        {"--field open -o " + folder.file("d.ply"), "unbounded", 2},
        {"--field rign -o " + folder.file("e.ply"), "did you mean \"ring\"", 2},
        {"--field ring -o " + folder.file("f.stl"), "unknown mesh format", 2},
        {"--field ring -o " + folder.file("no/folder/g.ply"), "does not exist", 2},
    };
    for (const Case& c : cases) {
        const auto r = runIsotrace("polygonize " + scene + " " + c.arguments);
        EXPECT_EQ(r.exitCode, c.exitCode) << c.arguments << ": " << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.arguments << ": " << r.output;
    }
    EXPECT_EQ(filesIn(folder.path()), 1u) << "no mesh may be written";
    // A field with no surface in its bounds: an empty mesh and a warning.
    const auto empty = runIsotrace("polygonize " + scene + " --field nothing -o " + folder.file("empty.off"));
    EXPECT_EQ(empty.exitCode, 0) << empty.output;
    EXPECT_NE(empty.output.find("warning"), std::string::npos) << empty.output;
}

TEST(CommandLine, SampleWritesParticlesAndAReport) {
    TemporaryFolder folder;
    const std::string scene = folder.write("s.json", kFieldScene);
    const auto r = runIsotrace("sample " + scene + " --field ring --count 500 --seed 3 --report -o " + folder.file("ring.ply"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto report = nlohmann::json::parse(r.output);
    EXPECT_NEAR(report["count"].get<double>(), 500, 50);
    EXPECT_LT(report["max_distance"].get<double>(), 1e-6);
    EXPECT_LT(report["nearest_neighbour_variation"].get<double>(), 0.15);
    EXPECT_EQ(report["components"].size(), 1u);
    // Binary PLY: the header, then 7 floats per particle.
    const std::string ply = readFile(folder.file("ring.ply"));
    ASSERT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    const size_t body = ply.find("end_header\n") + 11;
    EXPECT_EQ(ply.size() - body, 28 * report["count"].get<size_t>());
    // Text points are what variational fields read: fit the ring from them.
    const auto xyz = runIsotrace("sample " + scene + " --field ring --spacing 0.2 -o " + folder.file("ring.xyz"));
    ASSERT_EQ(xyz.exitCode, 0) << xyz.output;
    const std::string fitted = folder.write("fitted.json", R"({"camera": {"from": [0, 0, 4], "to": [0, 0, 0]},
      "materials": {"clay": {"type": "diffuse"}},
      "fields": {"refit": {"type": "variational", "points": "ring.xyz"}},
      "objects": [{"field": "refit", "material": "clay"}]})");
    const auto render = runIsotrace("render " + fitted + " --width 8 --height 8 --spp 1 --no-preview -q -o " +
                                    folder.file("refit.exr"));
    EXPECT_EQ(render.exitCode, 0) << render.output;
}

TEST(CommandLine, SampleBadInput) {
    TemporaryFolder folder;
    const std::string scene = folder.write("s.json", kFieldScene);
    struct Case {
        std::string arguments, expect;
    };
    const std::vector<Case> cases{
        {"--field ring -o " + folder.file("a.ply") + " --count 0", "--count"},
        {"--field ring -o " + folder.file("b.ply") + " --spacing -0.1", "--spacing"},
        {"--field ring -o " + folder.file("c.ply") + " --spacing nan", "--spacing"},
        {"--field ring -o " + folder.file("d.ply"), "give one of --count and --spacing"},
        {"--field ring -o " + folder.file("e.ply") + " --count 10 --spacing 0.1", "excludes"},
        {"--field ring -o " + folder.file("f.ply") + " --spacing 1e-6", "10 million"},
        {"--field open -o " + folder.file("g.ply") + " --count 10", "unbounded"},
        {"--field nothing -o " + folder.file("h.ply") + " --count 10", "no surface"},
        {"--field rign -o " + folder.file("i.ply") + " --count 10", "did you mean \"ring\""},
        {"--field ring -o " + folder.file("j.obj") + " --count 10", "unknown point set format"},
        {"--field ring -o " + folder.file("k.ply") + " --count 10 --seed -1", "--seed"},
    };
    for (const Case& c : cases) {
        const auto r = runIsotrace("sample " + scene + " " + c.arguments);
        EXPECT_EQ(r.exitCode, 2) << c.arguments << ": " << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.arguments << ": " << r.output;
    }
    EXPECT_EQ(filesIn(folder.path()), 1u) << "no point set may be written";
}

TEST(CommandLine, RenderSwitchesEveryFieldObjectToAMesh) {
    TemporaryFolder folder;
    const std::string scene = folder.write("ball.json", kSmallScene);
    const auto r = runIsotrace("render " + scene + " --as mesh -o " + folder.file("m.exr") + " --quiet");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(runIsotrace("render " + scene + " --as triangles -o " + folder.file("x.exr")).exitCode, 2);
}

namespace {
// Renders kSmallScene (optionally edited) to `name` in `folder` with extra arguments.
std::string renderSmall(const TemporaryFolder& folder, const std::string& name, const std::string& arguments,
                        const std::string& scene = kSmallScene) {
    const std::string path = folder.write(name + ".json", scene);
    const auto r = runIsotrace("render " + path + " -o " + folder.file(name + ".exr") + " --no-preview --quiet " + arguments);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return folder.file(name + ".exr");
}
}  // namespace

// Four tiles rendered by four processes merge into the whole frame's bits.
TEST(CommandLine, TilesInFourProcessesMergeToTheWholeRenderBitForBit) {
    TemporaryFolder folder;
    const std::string whole = renderSmall(folder, "whole", "--width 40 --height 30 --spp 3 --seed 5 --threads 2");
    std::string tiles;
    for (int i = 0; i < 4; ++i)
        tiles += " " + renderSmall(folder, "tile" + std::to_string(i), "--width 40 --height 30 --spp 3 --seed 5 --threads 1 --tile " +
                                                                           std::to_string(i) + "/4");
    const auto merged = runIsotrace("merge" + tiles + " -o " + folder.file("merged.exr"));
    ASSERT_EQ(merged.exitCode, 0) << merged.output;
    const isotrace::Image a = isotrace::readImage(whole), b = isotrace::readImage(folder.file("merged.exr"));
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
    // A crop is the same bits as the matching window of the whole frame.
    const std::string crop = renderSmall(folder, "crop", "--width 40 --height 30 --spp 3 --seed 5 --crop 7 4 19 23");
    const isotrace::Image c = isotrace::readImage(crop);
    ASSERT_EQ(c.width, 12);
    EXPECT_EQ(c.x, 7);
    for (int y = 0; y < c.height; ++y)
        EXPECT_EQ(std::memcmp(c.pixel(0, y), a.pixel(7, 4 + y), 12 * 3 * sizeof(float)), 0) << "row " << y;
}

TEST(CommandLine, MergeRejectsGapsOverlapsAndForeignTiles) {
    TemporaryFolder folder;
    std::vector<std::string> t;
    for (int i = 0; i < 3; ++i)
        t.push_back(renderSmall(folder, "t" + std::to_string(i), "--width 20 --height 9 --spp 1 --tile " + std::to_string(i) + "/3"));
    const std::string otherSeed = renderSmall(folder, "seeded", "--width 20 --height 9 --spp 1 --seed 8 --tile 2/3");
    std::string edited = kSmallScene;
    edited.replace(edited.find("\"radius\": 1"), 11, "\"radius\": 0.9");
    const std::string otherScene = renderSmall(folder, "edited", "--width 20 --height 9 --spp 1 --tile 2/3", edited);
    struct Case {
        std::string tiles, expect;
    };
    for (const Case& c : {Case{t[0] + " " + t[1], "do not cover the frame"}, Case{t[0] + " " + t[1] + " " + t[1] + " " + t[2], "overlaps"},
                          Case{t[0] + " " + t[1] + " " + otherSeed, "isotrace:seed"},
                          Case{t[0] + " " + t[1] + " " + otherScene, "isotrace:scene_hash"},
                          Case{t[0] + " " + folder.file("missing.exr"), "missing.exr"}}) {
        const auto r = runIsotrace("merge " + c.tiles + " -o " + folder.file("m.exr"));
        EXPECT_EQ(r.exitCode, 2) << c.tiles << ": " << r.output;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
        EXPECT_FALSE(std::filesystem::exists(folder.file("m.exr")));
    }
    EXPECT_EQ(runIsotrace("render " + folder.file("t0.json") + " --tile 3/3 -o " + folder.file("x.exr")).exitCode, 2);
    EXPECT_EQ(runIsotrace("render " + folder.file("t0.json") + " --crop 0 0 999 5 -o " + folder.file("x.exr")).exitCode, 2);
    const auto both = runIsotrace("render " + folder.file("t0.json") + " --crop 0 0 4 4 --tile 0/2 -o " + folder.file("x.exr"));
    EXPECT_EQ(both.exitCode, 2);
    EXPECT_NE(both.output.find("not both"), std::string::npos) << both.output;
    EXPECT_FALSE(std::filesystem::exists(folder.file("x.exr")));
}

TEST(CommandLine, CompareExitCodesAndMetrics) {
    TemporaryFolder folder;
    const std::string a = renderSmall(folder, "a", "--spp 8 --seed 1");
    const std::string a2 = renderSmall(folder, "a2", "--spp 8 --seed 2");
    const std::string b = renderSmall(folder, "b", "--spp 8 --seed 3");
    std::string darker = kSmallScene;
    darker.replace(darker.find("\"type\": \"diffuse\""), 17, "\"type\": \"diffuse\", \"albedo\": [0.4, 0.4, 0.4]");
    const std::string changed = renderSmall(folder, "changed", "--spp 8 --seed 3", darker);

    EXPECT_EQ(runIsotrace("compare " + a + " " + a).exitCode, 0);
    EXPECT_EQ(runIsotrace("compare " + a + " " + b).exitCode, 1) << "noise differs at the default (tiny) threshold";
    EXPECT_EQ(runIsotrace("compare " + a + " " + b + " --fail 0.5").exitCode, 0);
    // Monte Carlo aware: another seed is within noise, a darker material is not.
    const auto noise = runIsotrace("compare " + b + " " + a + " --metric noise --noise " + a2 + " --json");
    EXPECT_EQ(noise.exitCode, 0) << noise.output;
    EXPECT_EQ(runIsotrace("compare " + changed + " " + a + " --metric noise --noise " + a2).exitCode, 1);
    const auto json = nlohmann::json::parse(runIsotrace("compare " + a + " " + b + " --fail 1 --json").output);
    EXPECT_EQ(json["verdict"], "PASS");
    EXPECT_GT(json["rmse"].get<double>(), 0.0);
    const auto diff = runIsotrace("compare " + a + " " + changed + " --fail 1 --diff " + folder.file("d.png"));
    EXPECT_EQ(diff.exitCode, 0);
    EXPECT_TRUE(std::filesystem::exists(folder.file("d.png")));
    // Bad input: a different size, an unreadable file.
    const std::string small = renderSmall(folder, "small", "--width 8 --height 8");
    const auto sizes = runIsotrace("compare " + a + " " + small);
    EXPECT_EQ(sizes.exitCode, 2);
    EXPECT_NE(sizes.output.find("16x12 differs from"), std::string::npos) << sizes.output;
    EXPECT_EQ(runIsotrace("compare " + a + " " + folder.file("none.exr")).exitCode, 2);
    const auto noNoise = runIsotrace("compare " + a + " " + b + " --metric noise");
    EXPECT_EQ(noNoise.exitCode, 2);
    EXPECT_NE(noNoise.output.find("needs --noise"), std::string::npos) << noNoise.output;
}

TEST(CommandLine, CompareWithFlipPicksTheVariantAndWritesAMagmaMap) {
    TemporaryFolder folder;
    const std::string a = renderSmall(folder, "a", "--spp 8 --seed 1");
    std::string darker = kSmallScene;
    darker.replace(darker.find("\"type\": \"diffuse\""), 17, "\"type\": \"diffuse\", \"albedo\": [0.2, 0.2, 0.2]");
    const std::string changed = renderSmall(folder, "changed", "--spp 8 --seed 1", darker);

    // EXR inputs are linear HDR data: HDR-FLIP.
    const auto same = nlohmann::json::parse(runIsotrace("compare " + a + " " + a + " --metric flip --json").output);
    EXPECT_EQ(same["flip"]["variant"], "hdr");
    EXPECT_EQ(same["value"].get<double>(), 0.0);
    EXPECT_EQ(same["verdict"], "PASS");
    const auto hdr = runIsotrace("compare " + changed + " " + a + " --metric flip --json --diff " + folder.file("flip.png"));
    EXPECT_EQ(hdr.exitCode, 1) << hdr.output;
    const auto hdrJson = nlohmann::json::parse(hdr.output);
    EXPECT_GT(hdrJson["flip"]["mean"].get<double>(), 0.05);
    EXPECT_GE(hdrJson["flip"]["exposures"].get<int>(), 2);

    // The map: magma runs from near black (no error) to pale yellow.
    const isotrace::Image map = isotrace::readImage(folder.file("flip.png"));
    EXPECT_EQ(map.width, 16);
    float darkest = 1, brightest = 0;
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            darkest = std::min(darkest, map.pixel(x, y)[0]);
            brightest = std::max(brightest, map.pixel(x, y)[0]);
            EXPECT_LE(map.pixel(x, y)[1], map.pixel(x, y)[0] + 1e-6) << "magma is never greener than red";
        }
    EXPECT_LT(darkest, 0.05f);
    EXPECT_GT(brightest, 0.3f);

    // The PNG previews are display-encoded: LDR-FLIP, and --metric flip-hdr forces the other.
    const std::string pa = folder.file("a.png"), pc = folder.file("changed.png");
    isotrace::writePreviewPng(pa, isotrace::readImage(a), 0.0);
    isotrace::writePreviewPng(pc, isotrace::readImage(changed), 0.0);
    const auto ldr = nlohmann::json::parse(runIsotrace("compare " + pc + " " + pa + " --metric flip --json").output);
    EXPECT_EQ(ldr["flip"]["variant"], "ldr");
    EXPECT_GT(ldr["value"].get<double>(), 0.0);
    const auto forced = nlohmann::json::parse(runIsotrace("compare " + pc + " " + pa + " --metric flip-hdr --json").output);
    EXPECT_EQ(forced["flip"]["variant"], "hdr");
    // A tighter viewing condition (fewer pixels per degree) is accepted; a silly one is not.
    EXPECT_EQ(runIsotrace("compare " + a + " " + a + " --metric flip --ppd 30").exitCode, 0);
    EXPECT_EQ(runIsotrace("compare " + a + " " + a + " --metric flip --ppd 0").exitCode, 2);
}

// Every metric's exit path on two 2x1 images with hand-computed differences:
// test (0.5, 0.5, 0.5 | 1, 1, 1) against reference (0.5, 0.5, 0.5 | 0.8, 0.8, 0.8).
// Squared errors 0.04 in three of six values: rmse sqrt(0.02) = 0.14142,
// psnr 16.99 dB, max 0.2, mean 0.1, relmse 0.02 / 0.65 = 0.030769 (0.04 / (0.64 + 0.01) in half),
// over: one of two pixels (0.2 > 0.1 * (0.8 + 0.05)).
TEST(CommandLine, CompareMetricExitPathsOnHandComputedImages) {
    TemporaryFolder folder;
    auto write = [&](const std::string& name, std::vector<float> rgb) {
        isotrace::Image image;
        image.width = 2;
        image.height = 1;
        image.rgb = std::move(rgb);
        isotrace::writeImage(folder.file(name), image, {}, false);
        return folder.file(name);
    };
    const std::string test = write("t.exr", {0.5f, 0.5f, 0.5f, 1, 1, 1});
    const std::string reference = write("r.exr", {0.5f, 0.5f, 0.5f, 0.8f, 0.8f, 0.8f});
    auto exitOf = [&](const std::string& arguments) { return runIsotrace("compare " + test + " " + reference + " " + arguments).exitCode; };
    EXPECT_EQ(exitOf("--metric rmse --fail 0.1415"), 0);
    EXPECT_EQ(exitOf("--metric rmse --fail 0.1414"), 1);
    EXPECT_EQ(exitOf("--metric psnr --fail 16.9"), 0);  // psnr fails when below
    EXPECT_EQ(exitOf("--metric psnr --fail 17.1"), 1);
    EXPECT_EQ(exitOf("--metric max --fail 0.2001"), 0);
    EXPECT_EQ(exitOf("--metric max --fail 0.1999"), 1);
    EXPECT_EQ(exitOf("--metric mean --fail 0.1001"), 0);
    EXPECT_EQ(exitOf("--metric mean --fail 0.0999"), 1);
    EXPECT_EQ(exitOf("--metric relmse --fail 0.0308"), 0);
    EXPECT_EQ(exitOf("--metric relmse --fail 0.0307"), 1);
    EXPECT_EQ(exitOf("--metric over --fail 0.51"), 0);
    EXPECT_EQ(exitOf("--metric over --fail 0.49"), 1);
    EXPECT_EQ(exitOf("--fail 1 --fail-percent 51"), 0);
    EXPECT_EQ(exitOf("--fail 1 --fail-percent 49"), 1);
    const auto warned = runIsotrace("compare " + test + " " + reference + " --fail 1 --warn 0.1");
    EXPECT_EQ(warned.exitCode, 0);
    EXPECT_NE(warned.output.find("WARN"), std::string::npos) << warned.output;
    const auto json = nlohmann::json::parse(runIsotrace("compare " + test + " " + reference + " --fail 1 --json").output);
    EXPECT_NEAR(json["rmse"].get<double>(), std::sqrt(0.02), 1e-6);
    EXPECT_NEAR(json["psnr"].get<double>(), -20 * std::log10(std::sqrt(0.02)), 1e-4);
    EXPECT_NEAR(json["relmse"].get<double>(), 0.02 / 0.65, 1e-6);

    // A NaN fails whatever the threshold, and is located.
    const std::string withNan = write("n.exr", {0.5f, std::nanf(""), 0.5f, 1, 1, 1});
    const auto nan = runIsotrace("compare " + withNan + " " + reference + " --fail 100");
    EXPECT_EQ(nan.exitCode, 1);
    EXPECT_NE(nan.output.find("first at (0, 0)"), std::string::npos) << nan.output;
    EXPECT_NE(nan.output.find("FAIL: 1 pixels are NaN or infinite"), std::string::npos) << nan.output;
    EXPECT_EQ(nan.output.find("(fail at"), std::string::npos) << "the verdict names the NaN, not a passing value: " << nan.output;
    // Different channel sets: bad input, naming them.
    isotrace::Image withAlpha;
    withAlpha.width = 2;
    withAlpha.height = 1;
    withAlpha.rgb = {0.5f, 0.5f, 0.5f, 1, 1, 1};
    withAlpha.extraChannels = {"A"};
    withAlpha.extra = {1, 1};
    isotrace::writeImage(folder.file("a.exr"), withAlpha, {}, false);
    const auto channels = runIsotrace("compare " + folder.file("a.exr") + " " + reference);
    EXPECT_EQ(channels.exitCode, 2);
    EXPECT_NE(channels.output.find("channels R,G,B,A differ"), std::string::npos) << channels.output;
}

// A fit that misses its points by far says why and what to change: on
// oni.pwn's thin parts (1,435 points) balls grown to 15 points miss by 16
// times an accuracy of 5e-4; the hint names min_points unless it is already
// at its least.
TEST(CommandLine, FitMpuThatMissesItsPointsSuggestsSmallerBalls) {
    TemporaryFolder folder;
    const std::string points = std::string(ISOTRACE_TEST_DATA_DIR) + "/oni.pwn";
    const auto loose = runIsotrace("fit " + points + " --method mpu --accuracy 0.0005 -o " + folder.file("a.json"));
    ASSERT_EQ(loose.exitCode, 0) << loose.output;
    EXPECT_NE(loose.output.find("too few points where the surface bends or folds (a smaller min_points"),
              std::string::npos)
        << loose.output;
    const auto least =
        runIsotrace("fit " + points + " --method mpu --accuracy 0.0005 --min-points 6 -o " + folder.file("b.json"));
    ASSERT_EQ(least.exitCode, 0) << least.output;
    EXPECT_EQ(least.output.find("a smaller min_points"), std::string::npos) << least.output;
}

// --method mpu: the saved fit loads in a scene, renders the same field as
// fitting it in the scene, and its summary counts what was built.
TEST(CommandLine, FitMpuWritesAFieldScenesLoad) {
    TemporaryFolder folder;
    const std::string fitted = folder.file("sphere.mpu.json");
    const std::string points = std::string(ISOTRACE_TEST_DATA_DIR) + "/sphere926.pwn";
    const auto fit = runIsotrace("fit " + points + " --method mpu --accuracy 0.004 -o " + fitted);
    ASSERT_EQ(fit.exitCode, 0) << fit.output;
    EXPECT_NE(fit.output.find("fitted 926 oriented points with "), std::string::npos) << fit.output;
    const auto saved = nlohmann::json::parse(std::ifstream(fitted));
    EXPECT_EQ(saved["source"]["points"]["count"], 926);
    EXPECT_EQ(saved["source"]["accuracy"], 0.004);
    EXPECT_GT(saved["locals"].size(), 8u);
    EXPECT_LT(saved["fit"]["max_error"].get<double>(), 0.012);
    EXPECT_GT(saved["fit"]["mean_error"].get<double>(), 0.0);
    EXPECT_LT(saved["fit"]["mean_error"].get<double>(), saved["fit"]["max_error"].get<double>());

    std::string scene = kSmallScene;
    const std::string sphere = "{\"type\": \"sphere\", \"radius\": 1}";
    scene.replace(scene.find(sphere), sphere.size(), "{\"type\": \"mpu\", \"fitted\": \"sphere.mpu.json\"}");
    const std::string loaded = folder.write("loaded.json", scene);
    std::string inline_ = kSmallScene;
    inline_.replace(inline_.find(sphere), sphere.size(),
                    "{\"type\": \"mpu\", \"accuracy\": 0.004, \"points\": \"" + points + "\"}");
    const std::string fittedHere = folder.write("inline.json", inline_);
    for (const std::string& s : {loaded, fittedHere}) {
        const auto r = runIsotrace("render " + s + " --width 24 --height 16 --spp 2 --no-preview -o " + s + ".exr");
        ASSERT_EQ(r.exitCode, 0) << r.output;
    }
    const auto same = runIsotrace("compare " + loaded + ".exr " + fittedHere + ".exr --metric max --fail 0");
    EXPECT_EQ(same.exitCode, 0) << same.output;
}

// --solver partition (what fits past 20,000 unknowns use by themselves):
// the saved MPU form loads as a variational field and polygonizes to a sphere.
TEST(CommandLine, FitSolverPartitionWritesLocalInterpolants) {
    TemporaryFolder folder;
    const std::string fitted = folder.file("sphere.fit.json");
    const auto fit = runIsotrace("fit " + std::string(ISOTRACE_TEST_DATA_DIR) + "/sphere926.pwn --solver partition -o " + fitted);
    ASSERT_EQ(fit.exitCode, 0) << fit.output;
    EXPECT_NE(fit.output.find("fitted 1852 constraints by a partition of"), std::string::npos) << fit.output;
    const auto saved = nlohmann::json::parse(std::ifstream(fitted));
    EXPECT_GT(saved["interpolants"].size(), 10u);
    EXPECT_EQ(saved["source"]["solver"], "partition");
    EXPECT_LT(saved["fit"]["max_error"].get<double>(), 1e-6);
    std::string scene = kSmallScene;
    scene.replace(scene.find("{\"type\": \"sphere\", \"radius\": 1}"), 31,
                  "{\"type\": \"variational\", \"fitted\": \"sphere.fit.json\"}");
    const auto mesh = runIsotrace("polygonize " + folder.write("fitted.json", scene) +
                                  " --field ball --resolution 24 --report -o " + folder.file("ball.ply"));
    ASSERT_EQ(mesh.exitCode, 0) << mesh.output;
    EXPECT_EQ(nlohmann::json::parse(mesh.output)["euler_characteristic"], 2);
    const auto wrong = runIsotrace("fit " + std::string(ISOTRACE_TEST_DATA_DIR) + "/sphere926.pwn --method mpu --solver dense -o " +
                                   folder.file("x.json"));
    EXPECT_EQ(wrong.exitCode, 2);
    EXPECT_NE(wrong.output.find("--solver are options of --method variational"), std::string::npos) << wrong.output;
}

TEST(CommandLine, FitWritesAFieldScenesLoadAndRefusesBadInput) {
    TemporaryFolder folder;
    const std::string fitted = folder.file("sphere.fit.json");
    const auto fit = runIsotrace("fit " + std::string(ISOTRACE_TEST_DATA_DIR) + "/sphere926.pwn -o " + fitted);
    ASSERT_EQ(fit.exitCode, 0) << fit.output;
    EXPECT_NE(fit.output.find("fitted 1852 value and 0 gradient constraints (1856 unknowns)"), std::string::npos)
        << fit.output;
    const auto saved = nlohmann::json::parse(std::ifstream(fitted));
    EXPECT_EQ(saved["centers"].size(), 1852u);
    EXPECT_EQ(saved["source"]["points"]["count"], 926);
    EXPECT_LT(saved["fit"]["max_residual"].get<double>(), 1e-7);

    // A scene loads it without fitting again: polygonized, it is a sphere
    // (one component, Euler characteristic 2). (Sphere tracing it at its
    // full 1,852 terms per step is slow until the fast evaluator lands.)
    std::string scene = kSmallScene;
    scene.replace(scene.find("{\"type\": \"sphere\", \"radius\": 1}"), 31,
                  "{\"type\": \"variational\", \"fitted\": \"sphere.fit.json\"}");
    const std::string scenePath = folder.write("fitted.json", scene);
    const auto mesh = runIsotrace("polygonize " + scenePath + " --field ball --resolution 24 --report -o " +
                                  folder.file("ball.ply"));
    ASSERT_EQ(mesh.exitCode, 0) << mesh.output;
    const auto report = nlohmann::json::parse(mesh.output);
    EXPECT_EQ(report["euler_characteristic"], 2);
    EXPECT_EQ(report["watertight"], true);

    // Bad input: nothing written, exit 2, the file named.
    const std::string out = folder.file("bad.fit.json");
    // Points on a line with normals along z: with their offset points, all in the plane y = 0.
    const std::string flat = folder.write("flat.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n2 0 0 0 0 1\n3 0 0 0 0 1\n");
    const std::string malformed = folder.write("malformed.xyz", "0 0 0 0 0 1\n0 0 x 0 0 1\n");
    struct Case {
        std::string arguments, message;
    } cases[] = {
        {"fit " + folder.file("none.off") + " -o " + out, "not found"},
        {"fit " + malformed + " -o " + out, "line 2"},
        {"fit " + flat + " -o " + out, "lie in one plane"},
        {"fit " + flat + " -o " + folder.file("no/such/folder.json"), "does not exist"},
        {"fit " + flat + " -o " + out + " --normal-offset -1", "normal-offset"},
        {"fit " + flat + " -o " + out + " --margin 0", "margin"},
    };
    for (const Case& c : cases) {
        const auto r = runIsotrace(c.arguments);
        EXPECT_EQ(r.exitCode, 2) << c.arguments;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.arguments << ": " << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << c.arguments;
    }
    // Errors in the input name it as typed, not as the description the
    // command line became ("command line: /mesh: /abs/path").
    const auto missing = runIsotrace("fit " + folder.file("none.off") + " -o " + out);
    EXPECT_NE(missing.output.find("error: " + folder.file("none.off") + ": mesh file not found"), std::string::npos)
        << missing.output;
    EXPECT_EQ(missing.output.find("command line"), std::string::npos) << missing.output;
    const auto line = runIsotrace("fit " + malformed + " -o " + out);
    EXPECT_NE(line.output.find("error: " + malformed + ": line 2: "), std::string::npos) << line.output;

    // Point sets are told from meshes by extension in any case, as scenes
    // read them: an upper-case .PWN is points, not a mesh format.
    const std::string shouting = folder.file("SPHERE.PWN");
    std::filesystem::copy_file(std::string(ISOTRACE_TEST_DATA_DIR) + "/sphere926.pwn", shouting);
    const auto upper = runIsotrace("fit " + shouting + " -o " + folder.file("upper.fit.json"));
    EXPECT_EQ(upper.exitCode, 0) << upper.output;
    EXPECT_NE(upper.output.find("fitted 1852 value"), std::string::npos) << upper.output;
}

// An output that is one of the inputs (however it is spelt) or not a
// regular file is refused before any work: exit 2, the input unchanged.
// A model whose faces carry their own copies of shared corners (UV seams)
// was refused ("value constraints coincide"); fit welds them, says how many,
// and fits exactly what the clean model gives.
TEST(CommandLine, FitWeldsCoincidentVerticesOfRealModels) {
    TemporaryFolder folder;
    const std::string clean = folder.write("clean.off",
        "OFF\n4 4 0\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n");
    const std::string seams = folder.write("seams.off",
        "OFF\n12 5 0\n1 1 1\n1 -1 -1\n-1 1 -1\n1 1 1\n-1 -1 1\n1 -1 -1\n1 1 1\n-1 1 -1\n-1 -1 1\n"
        "1 -1 -1\n-1 -1 1\n-1 1 -1\n3 0 1 2\n3 3 4 5\n3 6 7 8\n3 9 10 11\n3 0 3 6\n");
    const auto a = runIsotrace("fit " + clean + " -o " + folder.file("clean.fit.json"));
    const auto b = runIsotrace("fit " + seams + " -o " + folder.file("seams.fit.json"));
    ASSERT_EQ(a.exitCode, 0) << a.output;
    ASSERT_EQ(b.exitCode, 0) << b.output;
    EXPECT_NE(b.output.find("welded 8 vertices that coincide with others and dropped 1 degenerate triangles"),
              std::string::npos) << b.output;
    const auto fa = nlohmann::json::parse(std::ifstream(folder.file("clean.fit.json")));
    const auto fb = nlohmann::json::parse(std::ifstream(folder.file("seams.fit.json")));
    EXPECT_EQ(fa["weights"], fb["weights"]);
    EXPECT_EQ(fb["source"]["mesh"]["welded_vertices"], 8);
}

TEST(CommandLine, OutputsNeverReplaceInputsOrNonFiles) {
    TemporaryFolder folder;
    const std::string scene = folder.write("s.json", kSmallScene);
    const std::string text = readFile(scene);
    const std::string dotted = folder.path().string() + "/./s.json";
    auto refused = [&](const std::string& args, const std::string& what) {
        const auto r = runIsotrace(args);
        EXPECT_EQ(r.exitCode, 2) << args;
        EXPECT_NE(r.output.find(what), std::string::npos) << args << "\n" << r.output;
    };
    refused("render " + scene + " -o " + dotted + " -q", "is also an input");
    EXPECT_EQ(readFile(scene), text);
    refused("render " + scene + " -o /dev/null -q", "not a regular file");
    refused("render " + scene + " -o " + folder.path().string() + " -q", "not a regular file");
    const std::string image = folder.file("a.exr");
    ASSERT_EQ(runIsotrace("render " + scene + " -o " + image + " -q --no-preview").exitCode, 0);
    refused("compare " + image + " " + image + " --diff " + folder.path().string() + "/./a.exr", "is also an input");
    refused("merge " + image + " -o " + image, "is also an input");
    const std::string tetrahedron = folder.write("tet.off", "OFF\n4 4 0\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n"
                                                             "3 0 1 2\n3 0 3 1\n3 0 2 3\n3 1 3 2\n");
    const std::string mesh = readFile(tetrahedron);
    refused("fit " + tetrahedron + " -o " + folder.path().string() + "/../" + folder.path().filename().string() + "/tet.off -q",
            "is also an input");
    EXPECT_EQ(readFile(tetrahedron), mesh);
    EXPECT_EQ(readFile(scene), text);
}

TEST(CommandLine, NonFiniteAndNegativeNumbersAreRefused) {
    for (const char* args : {"render x.json --exposure nan", "render x.json --exposure inf", "render x.json --seed -1",
                             "render x.json --seed 18446744073709551616", "fit x.off -o y.json --margin nan",
                             "fit x.off -o y.json --normal-offset inf", "polygonize x.json --field f -o m.ply --tolerance nan",
                             "compare a.exr b.exr --pixel-threshold nan"}) {
        const auto r = runIsotrace(args);
        EXPECT_EQ(r.exitCode, 2) << args;
        EXPECT_NE(r.output.find("found"), std::string::npos) << args << "\n" << r.output;
    }
}

// Renders (EXR and PNG preview), tiles, merges and comparisons of EXRs
// never load OpenImageIO, whose Debian build maps some 250 libraries at
// start-up: with its module made unloadable they all still work. What does
// need it (reading a PNG) fails with a clear error, and writes nothing.
TEST(CommandLine, RendersMergesAndComparesWithoutOpenImageIo) {
    TemporaryFolder folder;
    const std::string scene = folder.write("scene.json", kSmallScene);
    const std::string without = "ISOTRACE_OPENIMAGEIO_MODULE=" + folder.file("absent.so") + " " ISOTRACE_EXECUTABLE " ";
    auto run = [&](const std::string& arguments) { return isotrace::testing::runShell(without + arguments); };
    const auto whole = run("render " + scene + " --seed 3 -q -o " + folder.file("whole.exr"));
    ASSERT_EQ(whole.exitCode, 0) << whole.output;
    EXPECT_TRUE(std::filesystem::exists(folder.file("whole.png")));
    for (int i = 0; i < 2; ++i) {
        const auto tile = run("render " + scene + " --seed 3 -q --no-preview --tile " + std::to_string(i) + "/2 -o " +
                              folder.file("t" + std::to_string(i) + ".exr"));
        ASSERT_EQ(tile.exitCode, 0) << tile.output;
    }
    const auto merge = run("merge " + folder.file("t0.exr") + " " + folder.file("t1.exr") + " -o " + folder.file("m.exr"));
    ASSERT_EQ(merge.exitCode, 0) << merge.output;
    const auto same = run("compare " + folder.file("whole.exr") + " " + folder.file("m.exr") + " --metric rmse --fail 0");
    EXPECT_EQ(same.exitCode, 0) << same.output;

    // The preview PNG, written by libpng, reads back through OpenImageIO
    // with the EXR's pixels in sRGB.
    auto in = OIIO::ImageInput::open(folder.file("whole.png"));
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().width, 16);
    std::vector<unsigned char> png(16 * 12 * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, png.data()));
    const isotrace::Image exr = isotrace::readImage(folder.file("whole.exr"));
    for (size_t i = 0; i < png.size(); ++i) {
        const double v = std::clamp(double(exr.rgb[i]), 0.0, 1.0);
        const double srgb = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
        ASSERT_NEAR(png[i], srgb * 255.0, 0.5 + 1e-6) << "sample " << i;
    }

    const auto needsIt = run("compare " + folder.file("whole.png") + " " + folder.file("whole.png"));
    EXPECT_EQ(needsIt.exitCode, 2) << needsIt.output;
    EXPECT_NE(needsIt.output.find("cannot load the OpenImageIO module"), std::string::npos) << needsIt.output;
    EXPECT_NE(needsIt.output.find("absent.so"), std::string::npos) << needsIt.output;
}

// Assimp (with Draco) added some 350 page faults to every process start; it
// is loaded only when a polygon model file is read or a PLY or OBJ written.
// With its module made unloadable, scenes without meshes still render and
// OFF still writes; a mesh in a scene or a PLY to write fails clearly, with
// exit 2 and no output file.
TEST(CommandLine, RendersWithoutAssimpUntilAMeshFileIsNeeded) {
    TemporaryFolder folder;
    const std::string scene = folder.write("scene.json", kSmallScene);
    const std::string without = "ISOTRACE_ASSIMP_MODULE=" + folder.file("absent.so") + " " ISOTRACE_EXECUTABLE " ";
    auto run = [&](const std::string& arguments) { return isotrace::testing::runShell(without + arguments); };
    const auto render = run("render " + scene + " -q -o " + folder.file("ball.exr"));
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_TRUE(std::filesystem::exists(folder.file("ball.exr")));
    const auto off = run("polygonize " + scene + " --field ball --resolution 16 -o " + folder.file("ball.off"));
    ASSERT_EQ(off.exitCode, 0) << off.output;

    // The mesh written above, read back as an object of a scene.
    const std::string withMesh = folder.write(
        "with_mesh.json", R"({"camera": {"from": [0, 0, 4], "to": [0, 0, 0]}, "film": {"width": 8, "height": 6, "spp": 1},
          "materials": {"clay": {"type": "diffuse"}},
          "objects": [{"mesh": ")" + folder.file("ball.off") + R"(", "material": "clay"}],
          "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})");
    for (const std::string& arguments : {"render " + withMesh + " -q -o " + folder.file("mesh.exr"),
                                         "polygonize " + scene + " --field ball --resolution 16 -o " + folder.file("ball.ply")}) {
        const auto needsIt = run(arguments);
        EXPECT_EQ(needsIt.exitCode, 2) << arguments << "\n" << needsIt.output;
        EXPECT_NE(needsIt.output.find("cannot load the Assimp module"), std::string::npos) << needsIt.output;
        EXPECT_NE(needsIt.output.find("absent.so"), std::string::npos) << needsIt.output;
    }
    EXPECT_FALSE(std::filesystem::exists(folder.file("mesh.exr")));
    EXPECT_FALSE(std::filesystem::exists(folder.file("mesh.png")));
    EXPECT_FALSE(std::filesystem::exists(folder.file("ball.ply")));

    // With the module where the executable finds it, the same mesh renders.
    const auto found = runIsotrace("render " + withMesh + " -q -o " + folder.file("mesh.exr"));
    EXPECT_EQ(found.exitCode, 0) << found.output;
}
