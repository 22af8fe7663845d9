// The "mpu" field description: the saved fit (exact round trip, sharp
// pieces included), the content-hash cache on disk and malformed saved fits.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/description/mpu_description.h"
#include "support/temporary_files.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::TemporaryFolder;
using isotrace::testing::testDataFile;

namespace {

size_t filesIn(const std::string& folder) {
    size_t n = 0;
    if (std::filesystem::exists(folder))
        for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(folder)) ++n;
    return n;
}

// Points on the faces of the cube [-1, 1]^3: a fit with corner functions,
// so the saved form carries pieces combined by max.
std::string writeCubePoints(const TemporaryFolder& folder) {
    const std::string path = folder.file("cube.xyz");
    std::ofstream out(path);
    out.precision(17);
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0})
            for (int i = 0; i < 24; ++i)
                for (int j = 0; j < 24; ++j) {
                    Vec3 p, n = Vec3::Zero();
                    p[axis] = sign, n[axis] = sign;
                    p[(axis + 1) % 3] = -1 + (i + 0.5) / 12, p[(axis + 2) % 3] = -1 + (j + 0.5) / 12;
                    out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
                }
    return path;
}

std::string loadError(const Json& saved) {
    try {
        mpuFieldFromJson(saved, "saved.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// A fit loaded from its saved form (the cache's, or `isotrace fit`'s)
// evaluates as the fresh one did, to the last bit: values, and the bounds
// tracing uses. A cube's sharp corners, and a curved scan, whose local
// frames are off the axes (their quadrics must be stored symmetric).
void expectSavedFitLoadsBitIdentically(const TemporaryFolder& folder, const std::string& points, Box3 box, bool sharp) {
    const Json description = {{"type", "mpu"}, {"points", points}};
    JsonObjectReader reader(description, "/fields/m", "scene.json");
    reader.string("type");
    VariationalContext context;
    const MpuSource source = readMpuSource(reader, context);
    MpuReport report;
    const MpuField fitted = fitMpuSource(source, reader, report, {});
    if (sharp) {
        ASSERT_GT(report.corners, 0u);
    }
    std::ofstream(folder.file("fit.json")) << mpuFieldToJson(fitted, report, source.provenance, source.hash).dump();

    const FieldLibrary library(Json::parse(R"({"m": {"type": "mpu", "fitted": "fit.json"}})"), "/fields",
                               folder.file("scene.json"));
    const FieldProgram loaded = library.compile("m");
    const Box3 domain = fitted.bounds();
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = domain.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(domain.extent());
        ASSERT_EQ(loaded.value(p), fitted.value(p)) << points << " at " << p.transpose();
    }
    // Bounds for tracing too (the program widens them: compare the fields).
    const MpuField reread = mpuFieldFromJson(parseJsonFile(folder.file("fit.json")), "fit.json");
    if (box.isEmpty()) box = Box3(domain.center() - 0.1 * domain.extent(), domain.center() + 0.05 * domain.extent());
    EXPECT_EQ(reread.range(box).lo, fitted.range(box).lo) << points;
    EXPECT_EQ(reread.range(box).hi, fitted.range(box).hi) << points;
    EXPECT_EQ(reread.lipschitz(box), fitted.lipschitz(box)) << points;
}

}  // namespace

TEST(MpuDescription, SavedFitLoadsBitIdentically) {
    TemporaryFolder folder;
    expectSavedFitLoadsBitIdentically(folder, writeCubePoints(folder), Box3(Vec3(0.9, 0.8, 0.7), Vec3(1.1, 1.2, 1.05)),
                                      true);
    expectSavedFitLoadsBitIdentically(folder, std::string(ISOTRACE_SOURCE_DIR) + "/scenes/scans/kitten.xyz", Box3(),
                                      false);
}

TEST(MpuDescription, FitsAreCachedOnDiskByContent) {
    TemporaryFolder folder;
    const std::string cacheFolder = folder.file("cache");
    const std::string fields = R"({"m": {"type": "mpu", "points": ")" + testDataFile("sphere926.pwn") + R"("}})";
    const FieldLibraryOptions options{std::make_shared<FitCache>(cacheFolder), {}};
    const FieldProgram first = FieldLibrary(Json::parse(fields), "/fields", "a.json", options).compile("m");
    ASSERT_EQ(filesIn(cacheFolder), 1u);
    // Another process (a new cache over the same folder) finds it on disk.
    const FieldLibraryOptions later{std::make_shared<FitCache>(cacheFolder), {}};
    const FieldProgram again = FieldLibrary(Json::parse(fields), "/fields", "b.json", later).compile("m");
    EXPECT_EQ(again.value(Vec3(0.1, 0.2, 0.3)), first.value(Vec3(0.1, 0.2, 0.3)));
    // Other options are another fit.
    const std::string coarser = R"({"m": {"type": "mpu", "accuracy": 0.01, "points": ")" + testDataFile("sphere926.pwn") + R"("}})";
    FieldLibrary(Json::parse(coarser), "/fields", "c.json", later).compile("m");
    EXPECT_EQ(filesIn(cacheFolder), 2u);
    // A damaged entry is refitted, not trusted.
    for (const auto& e : std::filesystem::directory_iterator(cacheFolder)) std::ofstream(e.path()) << "{ damaged";
    const FieldLibraryOptions fresh{std::make_shared<FitCache>(cacheFolder), {}};
    const FieldProgram refitted = FieldLibrary(Json::parse(fields), "/fields", "d.json", fresh).compile("m");
    EXPECT_EQ(refitted.value(Vec3(0.1, 0.2, 0.3)), first.value(Vec3(0.1, 0.2, 0.3)));
}

TEST(MpuDescription, MalformedSavedFitsNameThePlace) {
    TemporaryFolder folder;
    const Json description = {{"type", "mpu"}, {"points", testDataFile("sphere926.pwn")}, {"accuracy", 0.01}};
    JsonObjectReader reader(description, "/fields/m", "scene.json");
    reader.string("type");
    VariationalContext context;
    const MpuSource source = readMpuSource(reader, context);
    MpuReport report;
    const Json good = mpuFieldToJson(fitMpuSource(source, reader, report, {}), report, source.provenance, source.hash);
    EXPECT_EQ(loadError(good), "");

    auto damaged = [&](auto&& change) {
        Json j = good;
        change(j);
        return loadError(j);
    };
    EXPECT_NE(loadError(Json::object()).find("not a fitted MPU field"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["isotrace_mpu_fit"] = 7; }).find("format version 7"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["locals"][3][6] = "maximum"; }).find("saved.json: /locals/3/6"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["locals"][0][4] = 1u << 30; }).find("out of range"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["locals"][0][5] = 2; }).find("does not fit its number of pieces"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["locals"][0][5] = -1; }).find("/locals/0/5: expected 1, 2 or 3"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["pieces"][2][12] = "x"; }).find("/pieces/2/12"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["pieces"][1].erase(0); }).find("/pieces/1: expected"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["support"] = 0.1; }).find("support"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["extra"] = 1; }).find("extra"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["locals"] = Json::array(); }).find("no local functions"), std::string::npos);

    // In a scene: the file and key of the reference come first.
    std::ofstream(folder.file("broken.json")) << "{\"isotrace_mpu_fit\": 1, \"domain\": 3}";
    try {
        FieldLibrary(Json::parse(R"({"m": {"type": "mpu", "fitted": "broken.json"}})"), "/fields", folder.file("scene.json"))
            .compile("m");
        FAIL() << "a broken saved fit loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/fields/m/fitted"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos) << e.what();
    }
}
