// Every scene in scenes/ renders at the settings of
// reference_images/render-settings.txt and matches its reference EXR.
// Regenerate on purpose with tests/update_reference_images.sh.
//
// Tolerance: with the same seed the renderer is deterministic, so on the
// machine that rendered the references the difference is zero. Another CPU
// or compiler may round a few operations differently and send a handful of
// paths elsewhere; such divergence touches few pixels. A real regression
// (shading, geometry, sampling) moves most pixels. So: the mean absolute
// difference must stay under 1% of the reference's mean, and at most 1% of
// pixels may differ by more than 25% (of their value plus 0.05).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "renderer/image_comparison.h"
#include "renderer/image_output.h"
#include "support/run_command.h"
#include "support/temporary_files.h"

using namespace isotrace;
using isotrace::testing::runIsotrace;
using isotrace::testing::TemporaryFolder;

namespace {

std::vector<std::string> sceneNames() {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(ISOTRACE_SOURCE_DIR) + "/scenes"))
        if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

class SceneRegression : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(SceneRegression, MatchesReferenceImage) {
    const std::string source = ISOTRACE_SOURCE_DIR;
    const std::string reference = source + "/reference_images/" + GetParam() + ".exr";
    ASSERT_TRUE(std::filesystem::exists(reference))
        << reference << " is missing; create it with tests/update_reference_images.sh " << GetParam();
    std::ifstream settingsFile(source + "/reference_images/render-settings.txt");
    std::string settings;
    std::getline(settingsFile, settings);
    TemporaryFolder folder;
    const auto r = runIsotrace("render " + source + "/scenes/" + GetParam() + ".json " + settings +
                               " --threads 2 --no-preview --quiet -o " + folder.file("test.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageDifference d = compareImages(readImage(folder.file("test.exr")), readImage(reference), 0.25);
    EXPECT_EQ(d.nonFinite, 0);
    EXPECT_LE(d.meanAbsolute, 0.01 * d.referenceMean) << "mean absolute difference " << d.meanAbsolute;
    EXPECT_LE(d.fractionOver, 0.01) << "fraction of differing pixels " << d.fractionOver;
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneRegression, ::testing::ValuesIn(sceneNames()),
                         [](const auto& info) { return info.param; });
