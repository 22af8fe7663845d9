// Image files appear whole or not at all: a disk that fills up while a
// preview PNG is written (simulated by a file-size limit in a child
// process) is an error, and leaves neither the PNG nor its temporary file.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include "renderer/image/image_output.h"
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
enum class Writer { Png, Exr, StreamedExr };
int writeWithFileSizeLimit(const std::string& path, Writer writer, rlim_t limitBytes) {
    const pid_t child = fork();
    if (child == 0) {
        const rlimit limit{limitBytes, limitBytes};
        setrlimit(RLIMIT_FSIZE, &limit);
        std::signal(SIGXFSZ, SIG_IGN);
        try {
            const Image image = noise(128, 128);
            if (writer == Writer::Png) {
                writePreviewPng(path, image, 0.0);
            } else if (writer == Writer::Exr) {
                writeImage(path, image, {}, false);
            } else {
                RenderExrWriter streamed(path, {}, false);
                streamed.rowsFinished(image, 100);
                streamed.finish(image);
            }
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
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("preview.png"), Writer::Png, 8192), 2);
    EXPECT_FALSE(std::filesystem::exists(folder.file("preview.png")));
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("image.exr"), Writer::Exr, 8192), 2);
    EXPECT_FALSE(std::filesystem::exists(folder.file("image.exr")));
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("streamed.exr"), Writer::StreamedExr, 8192), 2);
    EXPECT_FALSE(std::filesystem::exists(folder.file("streamed.exr")));
    EXPECT_EQ(filesIn(folder.path()), 0u) << "no temporary file left behind";
    // With room, all are written.
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("preview.png"), Writer::Png, RLIM_INFINITY), 0);
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("image.exr"), Writer::Exr, RLIM_INFINITY), 0);
    EXPECT_EQ(writeWithFileSizeLimit(folder.file("streamed.exr"), Writer::StreamedExr, RLIM_INFINITY), 0);
    EXPECT_EQ(filesIn(folder.path()), 3u);
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

// An EXR handed over in uneven bands of rows while they are made holds the
// same pixels as one written whole (float exactly, half alike), with the
// window, channels and metadata, and the late value filled in at its place.
TEST(ImageOutput, StreamedExrMatchesTheWholeWrite) {
    TemporaryFolder folder;
    Image image = noise(37, 53);
    image.x = 2;
    image.y = 9;
    image.fullWidth = 50;
    image.fullHeight = 70;
    image.extraChannels = {"Z", "id"};
    for (int i = 0; i < 2 * 37 * 53; ++i) image.extra.push_back(float(i % 97) - 3.5f);
    ImageMetadata metadata;
    metadata.strings = {{"isotrace:seed", "7"}};
    for (const bool half : {false, true}) {
        const std::string whole = folder.file(half ? "whole-half.exr" : "whole.exr");
        const std::string streamed = folder.file(half ? "streamed-half.exr" : "streamed.exr");
        writeImage(whole, image, metadata, half);
        RenderExrWriter writer(streamed, metadata, half, {{"isotrace:render_seconds", 16}});
        for (const int end : {1, 16, 17, 40, 52}) writer.rowsFinished(image, end);
        EXPECT_FALSE(std::filesystem::exists(streamed)) << "only a temporary file before finish";
        writer.finish(image, {{"isotrace:render_seconds", "12.5"}});  // the last row is handed over by finish
        ImageMetadata readWhole, readStreamed;
        const Image a = readImage(whole, &readWhole), b = readImage(streamed, &readStreamed);
        EXPECT_EQ(b.width, 37);
        EXPECT_EQ(b.height, 53);
        EXPECT_EQ(b.x, 2);
        EXPECT_EQ(b.y, 9);
        EXPECT_EQ(b.fullWidth, 50);
        EXPECT_EQ(b.fullHeight, 70);
        EXPECT_EQ(b.extraChannels, image.extraChannels);
        ASSERT_EQ(a.rgb.size(), b.rgb.size());
        ASSERT_EQ(a.extra.size(), b.extra.size());
        EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
        EXPECT_EQ(std::memcmp(a.extra.data(), b.extra.data(), a.extra.size() * sizeof(float)), 0);
        if (!half) {
            EXPECT_EQ(std::memcmp(b.rgb.data(), image.rgb.data(), b.rgb.size() * sizeof(float)), 0);
        }
        EXPECT_EQ(metadataValue(readStreamed, "isotrace:seed"), "7");
        EXPECT_EQ(metadataValue(readStreamed, "isotrace:render_seconds"), "12.5" + std::string(12, ' '));
    }
}

// A render that fails after some bands were written (the writer is
// destroyed unfinished) leaves neither the file nor its temporary.
TEST(ImageOutput, AnUnfinishedStreamedExrLeavesNothing) {
    TemporaryFolder folder;
    const Image image = noise(20, 40);
    {
        RenderExrWriter writer(folder.file("failed.exr"), {}, false);
        writer.rowsFinished(image, 16);
        EXPECT_EQ(filesIn(folder.path()), 1u) << "the temporary file";
    }
    EXPECT_EQ(filesIn(folder.path()), 0u);
}

// Bands out of order, a file finished with rows missing, and a late value
// wider than its room are refused.
TEST(ImageOutput, StreamedExrRefusesMisuse) {
    TemporaryFolder folder;
    ImageFile layout;
    layout.width = 4;
    layout.height = 20;
    layout.channelNames = {"R", "G", "B"};
    const std::vector<float> rgb(4 * 20 * 3, 0.25f);
    const std::vector<ChannelPlane> planes = {{rgb.data(), 3}, {rgb.data() + 1, 3}, {rgb.data() + 2, 3}};
    ExrRowWriter writer(folder.file("misused.exr"), layout, SampleFormat::Float, {{"late", 4}});
    writer.writeRows(planes, 10);
    EXPECT_THROW(writer.writeRows(planes, 5), std::invalid_argument);
    EXPECT_THROW(writer.writeRows(planes, 21), std::invalid_argument);
    EXPECT_THROW(writer.writeRows({planes[0]}, 15), std::invalid_argument);
    EXPECT_THROW(writer.finish({}), std::logic_error);
    writer.writeRows(planes, 20);
    EXPECT_THROW(writer.finish({{"late", "12345"}}), std::logic_error);
    EXPECT_THROW(writer.finish({{"unknown", "1"}}), std::logic_error);
}

// The preview's bytes are the sRGB encoding of the exposed value, rounded:
// values on either side of every byte's rounding point, beyond the ends,
// negative and NaN, read back through OpenImageIO.
TEST(ImageOutput, PreviewBytesAreRoundedSrgb) {
    auto encode = [](double v) {
        v = std::clamp(v, 0.0, 1.0);
        v = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
        return int(std::lround(v * 255.0));
    };
    auto decode = [](double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); };
    std::vector<float> values = {0.0f, -1.0f, 2.0f, 1.0f, std::numeric_limits<float>::infinity(),
                                 std::numeric_limits<float>::quiet_NaN(), 1e-6f};
    for (int k = 0; k < 255; ++k) {
        const double edge = decode((k + 0.5) / 255.0);
        values.push_back(float(edge * (1 - 1e-5)));
        values.push_back(float(edge * (1 + 1e-5)));
        values.push_back(float(decode(k / 255.0)));
    }
    while (values.size() % 3) values.push_back(0.5f);
    Image image;
    image.width = int(values.size() / 3);
    image.height = 1;
    image.rgb = values;
    const double exposure = 1.0;  // values are doubled before encoding
    TemporaryFolder folder;
    writePreviewPng(folder.file("p.png"), image, exposure);
    auto in = OIIO::ImageInput::open(folder.file("p.png"));
    ASSERT_TRUE(in);
    std::vector<unsigned char> bytes(values.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, bytes.data()));
    for (size_t i = 0; i < values.size(); ++i) {
        const double v = std::isnan(values[i]) ? 0.0 : 2.0 * values[i];
        EXPECT_EQ(int(bytes[i]), encode(v)) << "value " << values[i];
    }
}
