// `isotrace voxelize` and vdb fields as a user meets them: files other VDB
// tools read, and level sets that render, polygonize and compose like the
// fields they came from.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/temporary_files.h"

using isotrace::testing::runIsotrace;
using isotrace::testing::runShell;
using isotrace::testing::TemporaryFolder;

namespace {

const char* kTangleScene = R"({
  "camera": { "from": [4.5, 4.0, 6.5], "to": [0, 0, 0], "fov": 40 },
  "film": { "width": 64, "height": 64, "spp": 16 },
  "integrator": { "type": "path", "max_depth": 4 },
  "materials": { "glaze": { "type": "diffuse", "albedo": [0.8, 0.45, 0.2] } },
  "fields": { "tangle": { "type": "polynomial", "preset": "tangle" } },
  "objects": [ { "field": "tangle", "material": "glaze" } ],
  "lights": [ { "type": "disk", "center": [3, 8, 4], "normal": [-3, -8, -4], "radius": 1.5, "radiance": [12, 12, 11] },
              { "type": "environment", "radiance": [0.3, 0.3, 0.3] } ]
})";

// The same scene with the tangle read from `file` (`grid` in it), alone or
// cut by an analytic box.
std::string vdbScene(const std::string& file, bool cut) {
    nlohmann::json scene = nlohmann::json::parse(kTangleScene);
    scene["fields"] = {{"read", {{"type", "vdb"}, {"file", file}, {"grid", "surface"}}}};
    scene["fields"]["cut"] = {{"type", "difference"},
                              {"of", {"read", {{"type", "box"}, {"center", {1.5, 1.5, 1.5}}, {"size", {3, 3, 3}}}}}};
    scene["objects"][0]["field"] = cut ? "cut" : "read";
    return scene.dump(2);
}

double meanFlip(const std::string& a, const std::string& b) {
    const auto r = runIsotrace("compare " + a + " " + b + " --metric flip --json --fail 1e30");
    return nlohmann::json::parse(r.output)["flip"]["mean"].get<double>();
}

}  // namespace

TEST(Voxelize, WritesALevelSetThatOpenVdbToolsRead) {
    TemporaryFolder folder;
    const std::string scene = folder.write("tangle.json", kTangleScene), out = folder.file("tangle.vdb");
    const auto r = runIsotrace("voxelize " + scene + " --field tangle -o " + out + " --resolution 48 --report");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto report = nlohmann::json::parse(r.output);
    EXPECT_NEAR(report["voxel_size"].get<double>(), 6.0 / 48, 1e-12);
    EXPECT_GT(report["active_voxels"].get<int>(), 1000);
    if (runShell("command -v vdb_print").exitCode != 0) GTEST_SKIP() << "vdb_print (libopenvdb-tools) is not installed";
    const auto printed = runShell("vdb_print -l " + out);
    ASSERT_EQ(printed.exitCode, 0) << printed.output;
    for (const char* line : {"Name: surface", "class: level set", "voxel size: 0.125", "isotrace:field: tangle",
                             "isotrace:scene_hash: ", R"(isotrace:field_description: {"preset":"tangle","type":"polynomial"})"})
        EXPECT_NE(printed.output.find(line), std::string::npos) << line << "\n" << printed.output;
}

TEST(Voxelize, FogVolumesAreWrittenForVolumeRenderersAndRefusedAsSurfaces) {
    TemporaryFolder folder;
    const std::string scene = folder.write("tangle.json", kTangleScene), out = folder.file("fog.vdb");
    ASSERT_EQ(runIsotrace("voxelize " + scene + " --field tangle -o " + out + " --resolution 32 --fog --grid density").exitCode, 0);
    if (runShell("command -v vdb_print").exitCode == 0) {
        const auto printed = runShell("vdb_print -l " + out);
        EXPECT_NE(printed.output.find("class: fog volume"), std::string::npos) << printed.output;
        EXPECT_NE(printed.output.find("Name: density"), std::string::npos) << printed.output;
    }
    nlohmann::json read = nlohmann::json::parse(vdbScene(out, false));
    read["fields"]["read"]["grid"] = "density";
    const auto r = runIsotrace("render " + folder.write("fog.json", read.dump()) + " -o " + folder.file("x.exr"));
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("/fields/read/file"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("fog volume, not a level set"), std::string::npos) << r.output;
}

// Read back, the level set renders as the analytic tangle does: with the
// same samples, closer to it than a second run of the analytic one with
// other samples is; cut by an analytic box, it renders too.
TEST(Voxelize, ReadBackRendersAsTheFieldItCameFrom) {
    TemporaryFolder folder;
    const std::string scene = folder.write("tangle.json", kTangleScene), vdb = folder.file("tangle.vdb");
    ASSERT_EQ(runIsotrace("voxelize " + scene + " --field tangle -o " + vdb + " --resolution 96").exitCode, 0);
    const std::string analytic = folder.file("analytic.exr"), other = folder.file("other.exr"), read = folder.file("read.exr");
    ASSERT_EQ(runIsotrace("render " + scene + " -o " + analytic + " --seed 3 --quiet --no-preview").exitCode, 0);
    ASSERT_EQ(runIsotrace("render " + scene + " -o " + other + " --seed 4 --quiet --no-preview").exitCode, 0);
    const std::string readScene = folder.write("read.json", vdbScene(vdb, false));
    ASSERT_EQ(runIsotrace("render " + readScene + " -o " + read + " --seed 3 --quiet --no-preview").exitCode, 0);
    const double noise = meanFlip(other, analytic), error = meanFlip(read, analytic);
    EXPECT_LT(error, 0.5 * noise) << "read back " << error << ", another seed " << noise;
    // The cut removes an octant's lobes: the image changes by far more than noise.
    const std::string cut = folder.file("cut.exr");
    const auto r = runIsotrace("render " + folder.write("cut.json", vdbScene(vdb, true)) + " -o " + cut +
                               " --seed 3 --quiet --no-preview");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_GT(meanFlip(cut, read), 2 * noise);
}

// The committed torus, polygonized as a vdb field: one closed surface of genus 1.
TEST(Voxelize, VdbFieldsPolygonizeToClosedSurfacesOfTheirGenus) {
    TemporaryFolder folder;
    const std::string scene = folder.write(
        "torus.json", R"({"fields": {"torus": {"type": "vdb", "file": ")" ISOTRACE_TEST_DATA_DIR R"(/torus.vdb"}}})");
    const auto r = runIsotrace("polygonize " + scene + " --field torus -o " + folder.file("t.ply") + " --resolution 40 --report");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const auto report = nlohmann::json::parse(r.output);
    EXPECT_TRUE(report["watertight"].get<bool>());
    EXPECT_EQ(report["euler_characteristic"].get<int>(), 0);
}
