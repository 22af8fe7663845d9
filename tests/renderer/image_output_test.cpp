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
