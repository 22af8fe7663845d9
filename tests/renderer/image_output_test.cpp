// Image files appear whole or not at all: a disk that fills up while a
// preview PNG is written (simulated by a file-size limit in a child
// process) is an error, and leaves neither the PNG nor its temporary file.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <random>

#include "renderer/image_output.h"
#include "support/temporary_files.h"

using namespace isotrace;
using isotrace::testing::TemporaryFolder;

namespace {

Image noise(int width, int height) {
    Image image;
    image.width = width;
    image.height = height;
    image.rgb.resize(size_t(width) * height * 3);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0, 1);
    for (float& v : image.rgb) v = u(rng);  // incompressible: the PNG stays large
    return image;
}

// Writes in a child limited to `limitBytes` per file (SIGXFSZ ignored, so
// writes fail with EFBIG as on a full disk); returns the child's exit code:
// 0 written, 2 an error reported.
int writeWithFileSizeLimit(const std::string& path, bool png, rlim_t limitBytes) {
    const pid_t child = fork();
    if (child == 0) {
        const rlimit limit{limitBytes, limitBytes};
        setrlimit(RLIMIT_FSIZE, &limit);
        std::signal(SIGXFSZ, SIG_IGN);
        try {
            const Image image = noise(128, 128);
            if (png)
                writePreviewPng(path, image, 0.0);
            else
                writeImage(path, image, {}, false);
        } catch (const std::exception&) {
            _exit(2);
        }
        _exit(0);
    }
    int status = 0;
    waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

size_t filesIn(const std::filesystem::path& folder) {
    size_t n = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder)) ++n;
    return n;
}

}  // namespace

TEST(ImageOutput, AFullDiskFailsThePreviewAndLeavesNoFile) {
    TemporaryFolder folder;
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("preview.png"), true, 8192), 2);
    EXPECT_FALSE(std::filesystem::exists(folder.file("preview.png")));
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("image.exr"), false, 8192), 2);
    EXPECT_FALSE(std::filesystem::exists(folder.file("image.exr")));
    EXPECT_EQ(filesIn(folder.path()), 0u) << "no temporary file left behind";
    // With room, both are written.
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("preview.png"), true, RLIM_INFINITY), 0);
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("image.exr"), false, RLIM_INFINITY), 0);
    EXPECT_EQ(filesIn(folder.path()), 2u);
}

// EXR through OpenEXR: a window of a larger frame with AOV channels and
// metadata reads back as written (channels in the order renders write
// them, though the file keeps them sorted by name), exactly as float and
// to half precision as half.
TEST(ImageOutput, ExrKeepsWindowChannelsAndMetadata) {
    TemporaryFolder folder;
    Image image;
    image.width = 3;
    image.height = 2;
    image.x = 4;
    image.y = 1;
    image.fullWidth = 10;
    image.fullHeight = 5;
    image.extraChannels = {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z", "id", "steps"};
    std::mt19937 random(11);
    std::uniform_real_distribution<float> value(-4.0f, 4.0f);
    for (int i = 0; i < 3 * 6; ++i) image.rgb.push_back(value(random));
    for (size_t i = 0; i < image.extraChannels.size() * 6; ++i) image.extra.push_back(value(random));
    ImageMetadata metadata;
    metadata.strings = {{"isotrace:seed", "7"}, {"isotrace:scene", "a b.json"}};
    for (const bool half : {false, true}) {
        const std::string path = folder.file(half ? "half.exr" : "float.exr");
        writeImage(path, image, metadata, half);
        ImageMetadata read;
        const Image back = readImage(path, &read);
        EXPECT_EQ(back.width, 3);
        EXPECT_EQ(back.height, 2);
        EXPECT_EQ(back.x, 4);
        EXPECT_EQ(back.y, 1);
        EXPECT_EQ(back.fullWidth, 10);
        EXPECT_EQ(back.fullHeight, 5);
        EXPECT_EQ(back.extraChannels, image.extraChannels);
        // Half has an 11-bit significand: relative error at most 2^-11.
        const float tolerance = half ? 4.0f / 2048 : 0.0f;
        for (size_t i = 0; i < image.rgb.size(); ++i) EXPECT_NEAR(back.rgb[i], image.rgb[i], tolerance) << i;
        ASSERT_EQ(back.extra.size(), image.extra.size());
        for (size_t i = 0; i < image.extra.size(); ++i) EXPECT_NEAR(back.extra[i], image.extra[i], tolerance) << i;
        EXPECT_EQ(metadataValue(read, "isotrace:seed"), "7");
        EXPECT_EQ(metadataValue(read, "isotrace:scene"), "a b.json");
    }
}
