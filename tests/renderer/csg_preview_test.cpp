// `isotrace preview`: the contact sheet's layout, what each panel shows, and
// bad input.
#include <gtest/gtest.h>

#include <filesystem>

#include "renderer/image/image_output.h"
#include "support/run_command.h"
#include "support/temporary_files.h"

using isotrace::testing::runIsotrace;
using isotrace::testing::TemporaryFolder;

namespace {

// Two unit-ish spheres overlapping about the origin: A on the left, B on the right.
const char* kTwoSpheres = R"({"fields": {
  "left": {"type": "sphere", "center": [-0.4, 0, 0], "radius": 0.6},
  "right": {"type": "sphere", "center": [0.4, 0, 0], "radius": 0.6},
  "both": {"type": "union", "of": ["left", "right"]},
  "ball": {"type": "sphere", "radius": 1}}})";

constexpr int kPanelWidth = 64, kPanelHeight = 48, kGap = 4, kLabel = 24;

// Panel i of a 3x2 sheet: its top-left pixel (below the label).
std::pair<int, int> panelOrigin(int i) {
    return {kGap + (i % 3) * (kPanelWidth + kGap), kGap + (i / 3) * (kPanelHeight + kLabel + kGap) + kLabel};
}

// Pixels of the shape's orange (red well above blue) in panel i.
int shapePixels(const isotrace::Image& sheet, int i) {
    const auto [x0, y0] = panelOrigin(i);
    int n = 0;
    for (int y = 0; y < kPanelHeight; ++y)
        for (int x = 0; x < kPanelWidth; ++x) {
            const float* p = sheet.pixel(x0 + x, y0 + y);
            if (p[0] - p[2] > 0.15f) ++n;
        }
    return n;
}

// The two-spheres sheet at test size, with extra arguments, read back.
isotrace::Image previewSheet(const TemporaryFolder& folder, const std::string& arguments) {
    const std::string scene = folder.write("s.json", kTwoSpheres), sheet = folder.file("sheet.png");
    const auto r = runIsotrace("preview " + scene + " --field both -o " + sheet + arguments + " --panel-width " +
                               std::to_string(kPanelWidth) + " --panel-height " + std::to_string(kPanelHeight) +
                               " --spp 1 --quiet");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return isotrace::readImage(sheet);
}

}  // namespace

TEST(CsgPreview, SheetShowsOperandsAndTheirCombinations) {
    TemporaryFolder folder;
    const isotrace::Image image = previewSheet(folder, "");
    EXPECT_EQ(image.width, 3 * kPanelWidth + 4 * kGap);
    EXPECT_EQ(image.height, 2 * (kPanelHeight + kLabel) + 3 * kGap);

    int coverage[6];
    for (int i = 0; i < 6; ++i) coverage[i] = shapePixels(image, i);
    // A, B, union, intersection, A - B, B - A. Same camera in every panel.
    EXPECT_GT(coverage[0], 100);
    EXPECT_NEAR(coverage[0], coverage[1], 0.25 * coverage[0]) << "mirror images";
    EXPECT_GT(coverage[2], coverage[0]);
    EXPECT_LT(coverage[3], coverage[0]);
    EXPECT_GT(coverage[3], 0);
    EXPECT_LT(coverage[4], coverage[0]);
    EXPECT_LT(coverage[5], coverage[1]);

    // Every panel is labelled: white text in the dark strip above it.
    for (int i = 0; i < 6; ++i) {
        const auto [x0, y0] = panelOrigin(i);
        int bright = 0;
        for (int y = y0 - kLabel; y < y0; ++y)
            for (int x = x0; x < x0 + kPanelWidth; ++x) bright += image.pixel(x, y)[1] > 0.5f;
        EXPECT_GT(bright, 10) << "label of panel " << i;
    }
}

TEST(CsgPreview, SectionColoursInsideAndOutside) {
    TemporaryFolder folder;
    const isotrace::Image image = previewSheet(folder, " --section z=0");
    // The frame is symmetric about the origin, which is inside both spheres:
    // the centre pixel of each panel is inside (blue) for A, B, the union and
    // the intersection and outside (orange) for both differences.
    const bool insideExpected[6] = {true, true, true, true, false, false};
    for (int i = 0; i < 6; ++i) {
        const auto [x0, y0] = panelOrigin(i);
        const float* p = image.pixel(x0 + kPanelWidth / 2, y0 + kPanelHeight / 2);
        EXPECT_EQ(p[2] > p[0], insideExpected[i]) << "panel " << i << " rgb " << p[0] << " " << p[1] << " " << p[2];
    }
}

TEST(CsgPreview, BadInputIsRefusedWithoutWritingAFile) {
    TemporaryFolder folder;
    const std::string scene = folder.write("s.json", kTwoSpheres), sheet = folder.file("x.png");
    struct Case {
        std::string arguments, message;
    };
    const Case cases[] = {
        {"--field ball", "not a CSG node"},
        {"--field bothh", "did you mean \"both\""},
        {"--field both --section w", "expected x, y or z"},
        {"--field both --section z=abc", "not a finite number"},
        {"--field both --panel-width 0", "panel-width"},
        {"--field both --panel-height 100000", "panel-height"},
        {"--field both --spp 0", "spp"},
    };
    for (const Case& c : cases) {
        const auto r = runIsotrace("preview " + scene + " " + c.arguments + " -o " + sheet);
        EXPECT_EQ(r.exitCode, 2) << c.arguments;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.arguments << ": " << r.output;
        EXPECT_FALSE(std::filesystem::exists(sheet)) << c.arguments;
    }
    const std::string broken = folder.write("broken.json", "{\"fields\": {\"a\": ");
    const auto malformed = runIsotrace("preview " + broken + " --field a -o " + sheet);
    EXPECT_EQ(malformed.exitCode, 2);
    EXPECT_NE(malformed.output.find("broken.json"), std::string::npos) << malformed.output;
    const auto noFolder = runIsotrace("preview " + scene + " --field both -o " + folder.file("none/x.png"));
    EXPECT_EQ(noFolder.exitCode, 2);
    EXPECT_NE(noFolder.output.find("does not exist"), std::string::npos) << noFolder.output;
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.file("")), {}), 2) << "only the two scenes";
}

// A union of one operand has no B to show: an error at its operand list,
// not a read past it (AddressSanitizer found that read).
TEST(CsgPreview, NodeWithOneOperandIsAnError) {
    TemporaryFolder folder;
    const std::string scene = folder.write("one.json", R"({"fields": {"a": {"type": "sphere", "radius": 1},
      "one": {"type": "union", "of": ["a"]}}})");
    const auto r = runIsotrace("preview " + scene + " --field one -o " + folder.file("one.png") + " -q");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("/fields/one/of: a CSG node needs two operands or more"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(folder.file("one.png")));
}
