// The "variational" field description: sources, the saved fit (exact
// round trip), the content-hash cache and bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#include "geometry/field_parser.h"
#include "geometry/variational/variational_description.h"
#include "support/temporary_files.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::TemporaryFolder;
using isotrace::testing::testDataFile;

namespace {

// Each test caches into its own folder.
class CacheInFolder {
public:
    explicit CacheInFolder(const TemporaryFolder& folder) : path_(folder.file("cache")) {
        setenv("ISOTRACE_CACHE_DIR", path_.c_str(), 1);
    }
    ~CacheInFolder() { unsetenv("ISOTRACE_CACHE_DIR"); }
    size_t entries() const {
        size_t n = 0;
        if (std::filesystem::exists(path_))
            for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path_)) ++n;
        return n;
    }
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

std::string compileError(const std::string& fieldsJson, const std::string& file = "scene.json") {
    try {
        FieldLibrary(Json::parse(fieldsJson), "/fields", file).compile("v");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(VariationalDescription, InlineConstraintsCompileAndInterpolate) {
    TemporaryFolder folder;
    CacheInFolder cache(folder);
    const FieldLibrary library(Json::parse(R"({"v": {"type": "variational",
        "boundary": [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], "interior": [[0, 0, 0]]}})"),
                               "/fields", folder.file("scene.json"));
    const FieldProgram f = library.compile("v");
    EXPECT_NEAR(f.value(Vec3(1, 1, 1)), 0.0, 1e-12);
    EXPECT_NEAR(f.value(Vec3::Zero()), -1.0, 1e-12);
    // The domain holds the whole near-sphere, which reaches past the corners' box.
    EXPECT_GT(f.bounds().upper.x(), 1.6);
    EXPECT_GT(f.value(f.bounds().upper), 0.0);
}

TEST(VariationalDescription, SavedFitLoadsBitIdentically) {
    TemporaryFolder folder;
    CacheInFolder cache(folder);
    const std::string points = testDataFile("sphere926.pwn");
    const Json description = {{"type", "variational"}, {"points", points}};
    JsonObjectReader reader(description, "/fields/v", "scene.json");
    reader.string("type");
    const VariationalSource source = readVariationalSource(reader, "");
    FitReport report;
    const VariationalField fitted = fitVariationalField(source.constraints, &report, source.options);
    std::ofstream(folder.file("fit.json")) << variationalFieldToJson(fitted, report, source.provenance, source.hash).dump();

    const FieldLibrary library(Json::parse(R"({"v": {"type": "variational", "fitted": "fit.json"}})"), "/fields",
                               folder.file("scene.json"));
    const FieldProgram loaded = library.compile("v");
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p = fitted.domain.center() + 0.5 * Vec3(u(rng), u(rng), u(rng)).cwiseProduct(fitted.domain.extent());
        ASSERT_EQ(loaded.value(p), fitted.value(p)) << "at " << p.transpose();
    }
    EXPECT_EQ(cache.entries(), 0u) << "a saved fit needs no cache";
}

TEST(VariationalDescription, FitsAreCachedByContent) {
    TemporaryFolder folder;
    CacheInFolder cache(folder);
    const std::string fields = R"({"v": {"type": "variational", "points": ")" + testDataFile("sphere926.pwn") + R"(",
                                          "normal_offset": 0.02}})";
    const FieldProgram first = FieldLibrary(Json::parse(fields), "/fields", "a.json").compile("v");
    EXPECT_EQ(cache.entries(), 1u);
    // A damaged cache entry is refitted, not trusted. (The in-memory cache
    // holds the first fit, so change the content a little: another offset.)
    for (const auto& e : std::filesystem::directory_iterator(cache.path())) std::ofstream(e.path()) << "{ damaged";
    const std::string other = R"({"v": {"type": "variational", "points": ")" + testDataFile("sphere926.pwn") + R"(",
                                         "normal_offset": 0.03}})";
    FieldLibrary(Json::parse(other), "/fields", "a.json").compile("v");
    EXPECT_EQ(cache.entries(), 2u);
    const FieldProgram again = FieldLibrary(Json::parse(fields), "/fields", "b.json").compile("v");
    EXPECT_EQ(again.value(Vec3(0.1, 0.2, 0.3)), first.value(Vec3(0.1, 0.2, 0.3)));
}

TEST(VariationalDescription, BadInputNamesThePlace) {
    TemporaryFolder folder;
    CacheInFolder cache(folder);
    auto expectError = [](const std::string& fields, const std::string& where, const std::string& what) {
        const std::string e = compileError(fields);
        EXPECT_NE(e.find(where), std::string::npos) << e;
        EXPECT_NE(e.find(what), std::string::npos) << e;
    };
    expectError(R"({"v": {"type": "variational"}})", "/fields/v", "needs constraints");
    expectError(R"({"v": {"type": "variational", "boundary": [[0, 0, 0]], "normal_ofset": 1}})", "/fields/v/normal_ofset",
                "did you mean \"normal_offset\"");
    expectError(R"({"v": {"type": "variational", "boundary": [[0, 0]]}})", "/fields/v/boundary/0", "[x, y, z]");
    expectError(R"({"v": {"type": "variational", "values": [[0, 0, 0, "a"]]}})", "/fields/v/values/0/3", "finite number");
    expectError(R"({"v": {"type": "variational", "boundary": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "interior": [[0.2, 0.2, 0]]}})",
                "/fields/v", "lie in one plane");
    expectError(R"({"v": {"type": "variational", "boundary": [[0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 1, 0]], "interior": [[0.2, 0.2, 0.3]]}})",
                "/fields/v", "coincide");
    expectError(R"({"v": {"type": "variational", "points": "missing.xyz"}})", "/fields/v/points", "cannot open");
    expectError(R"({"v": {"type": "variational", "mesh": "missing.off"}})", "/fields/v/mesh", "not found");
    expectError(R"({"v": {"type": "variational", "fitted": "missing.json"}})", "/fields/v/fitted", "missing.json");

    const std::string badPoints = folder.write("bad.xyz", "0 0 0 0 0 1\n1 2 3 4 5\n");
    expectError(R"({"v": {"type": "variational", "points": ")" + badPoints + R"("}})", "line 2", "six numbers");
    const std::string zeroNormal = folder.write("zero.xyz", "0 0 0 0 0 0\n");
    expectError(R"({"v": {"type": "variational", "points": ")" + zeroNormal + R"("}})", "line 1", "normal is zero");
    const std::string notAFit = folder.write("notafit.json", R"({"centers": []})");
    expectError(R"({"v": {"type": "variational", "fitted": ")" + notAFit + R"("}})", "/fields/v/fitted",
                "not a fitted variational field");
    const std::string wrongCount = folder.write("wrong.json", R"({"isotrace_variational_fit": 1, "source": {}, "fit": {},
        "domain": [[-1, -1, -1], [1, 1, 1]], "constant": 0, "linear": [0, 0, 0], "centers": [[0, 0, 0]],
        "weights": [1, 2], "gradient_centers": [], "gradient_weights": []})");
    expectError(R"({"v": {"type": "variational", "fitted": ")" + wrongCount + R"("}})", "/weights", "2 weights for 1 centers");
}
