// Every scene in scenes/ renders at the settings of
// reference_images/render-settings.txt and matches its reference EXR.
// Regenerate on purpose with tests/update_reference_images.sh.
//
// Tolerance, from each render's own Monte Carlo noise, not from one CPU's
// bits. With the same seed the renderer is deterministic, so on the machine
// that rendered the references the difference is zero. Another CPU (Intel
// or AMD, AVX2 or AVX-512 kernels, another libm) rounds a few operations
// differently and sends some paths elsewhere; each such pixel then differs
// by at most what an independent sample would, so the difference stays
// within the render's noise. The test renders the scene a second time with
// another seed, estimates each pixel's variance from the pair, and scores
// the difference against it (noiseScore in renderer/image/image_comparison.h: the
// mean over 4x4 blocks of the squared block-mean difference over its
// variance, about 1 for pure noise and less where samples are shared). A
// limit of 3 leaves room for the variance estimate's own error (scores of
// independent renders were measured at 0.3 to 1.6), while a change of
// shading, geometry or sampling moves whole blocks and scores far above
// it: the test checks that a render a fifth brighter fails.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "renderer/image/image_comparison.h"
#include "renderer/image/image_output.h"
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

constexpr double kNoiseScoreLimit = 3.0;

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
    // The same settings with another seed.
    const size_t seedAt = settings.find("--seed 1");
    ASSERT_NE(seedAt, std::string::npos) << "the reference settings name seed 1";
    std::string secondSettings = settings;
    secondSettings.replace(seedAt, 8, "--seed 2");
    const auto second = runIsotrace("render " + source + "/scenes/" + GetParam() + ".json " + secondSettings +
                                    " --threads 2 --no-preview --quiet -o " + folder.file("second.exr"));
    ASSERT_EQ(second.exitCode, 0) << second.output;
    const Image test = readImage(folder.file("test.exr")), ref = readImage(reference);
    const Image secondSeed = readImage(folder.file("second.exr"));
    EXPECT_EQ(compareImages(test, ref).nonFinite, 0);
    const double score = noiseScore(test, ref, secondSeed);
    EXPECT_LE(score, kNoiseScoreLimit) << "differs from " << reference << " by more than its noise";
    // The limit can fail: the same render a fifth brighter is far outside it.
    Image brighter = test;
    for (float& v : brighter.rgb) v *= 1.2f;
    EXPECT_GT(noiseScore(brighter, ref, secondSeed), kNoiseScoreLimit) << "the scene's noise hides a 20% change";
    std::printf("%s: noise score %.3g\n", GetParam().c_str(), score);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneRegression, ::testing::ValuesIn(sceneNames()),
                         [](const auto& info) { return info.param; });
