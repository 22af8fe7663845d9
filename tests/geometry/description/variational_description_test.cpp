// The "variational" field description: sources, the saved fit (exact
// round trip), the content-hash cache and bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/description/mpu_description.h"
#include "geometry/description/variational_description.h"
#include "support/temporary_files.h"
#include "support/test_data.h"

using namespace isotrace::geometry;
using isotrace::testing::TemporaryFolder;
using isotrace::testing::testDataFile;

namespace {

// Each test caches into its own folder.
class CacheInFolder {
public:
    explicit CacheInFolder(const TemporaryFolder& folder)
        : path_(folder.file("cache")), fits_(std::make_shared<FitCache>(path_)) {}
    FieldLibraryOptions options() const { return {fits_, {}}; }
    size_t entries() const {
        size_t n = 0;
        if (std::filesystem::exists(path_))
            for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path_)) ++n;
        return n;
    }
    const std::string& path() const { return path_; }

private:
    std::string path_;
    std::shared_ptr<FitCache> fits_;
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
                               "/fields", folder.file("scene.json"), cache.options());
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
    VariationalContext context;
    const VariationalSource source = readVariationalSource(reader, context);
    FitReport report;
    const VariationalField fitted = fitVariationalField(source.constraints, &report, source.options);
    std::ofstream(folder.file("fit.json")) << variationalFieldToJson(fitted, report, source.provenance, source.hash).dump();

    const FieldLibrary library(Json::parse(R"({"v": {"type": "variational", "fitted": "fit.json"}})"), "/fields",
                               folder.file("scene.json"), cache.options());
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
    const FieldProgram first = FieldLibrary(Json::parse(fields), "/fields", "a.json", cache.options()).compile("v");
    EXPECT_EQ(cache.entries(), 1u);
    // A damaged cache entry is refitted, not trusted. (The in-memory cache
    // holds the first fit, so change the content a little: another offset.)
    for (const auto& e : std::filesystem::directory_iterator(cache.path())) std::ofstream(e.path()) << "{ damaged";
    const std::string other = R"({"v": {"type": "variational", "points": ")" + testDataFile("sphere926.pwn") + R"(",
                                         "normal_offset": 0.03}})";
    FieldLibrary(Json::parse(other), "/fields", "a.json", cache.options()).compile("v");
    EXPECT_EQ(cache.entries(), 2u);
    const FieldProgram again = FieldLibrary(Json::parse(fields), "/fields", "b.json", cache.options()).compile("v");
    EXPECT_EQ(again.value(Vec3(0.1, 0.2, 0.3)), first.value(Vec3(0.1, 0.2, 0.3)));
}

// The host decides where fits are kept: the library reads no environment.
TEST(VariationalDescription, TheLibraryCachesOnlyWhereItIsTold) {
    TemporaryFolder folder;
    const std::string unused = folder.file("environment-cache");
    setenv("ISOTRACE_CACHE_DIR", unused.c_str(), 1);
    const std::string fields = R"({"v": {"type": "variational", "points": ")" + testDataFile("sphere926.pwn") + R"("}})";
    FieldLibrary(Json::parse(fields), "/fields", "a.json").compile("v");
    unsetenv("ISOTRACE_CACHE_DIR");
    EXPECT_FALSE(std::filesystem::exists(unused));
    CacheInFolder cache(folder);
    FieldLibrary(Json::parse(fields), "/fields", "a.json", cache.options()).compile("v");
    EXPECT_EQ(cache.entries(), 1u);
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

    const std::string tetrahedron = R"("boundary": [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], "interior": [[0, 0, 0]])";
    expectError(R"({"v": {"type": "variational", )" + tetrahedron + R"(, "margin": -1}})", "/fields/v/margin", "");
    expectError(R"({"v": {"type": "variational", )" + tetrahedron + R"(, "hermite": "yes"}})", "/fields/v/hermite", "");
    expectError(R"({"v": {"type": "variational", "normals": [[0, 0, 0, 0, 0, 0]]}})", "/fields/v/normals", "zero vector");
    expectError(R"({"v": {"type": "variational", "sample": "nowhere"}})", "/fields/v/sample", "unknown field \"nowhere\"");
    expectError(R"({"ball": {"type": "sphere", "radius": 1}, "v": {"type": "variational", "sample": "ball", "count": 2}})",
                "/fields/v/count", "");
    expectError(R"({"v": {"type": "variational", "blend": "a"}})", "/fields/v/blend", "at least two variational fields");

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

namespace {
// Normal constraints of a sphere as a "normals" array.
Json sphereNormals(const Vec3& center, double radius, int count) {
    Json rows = Json::array();
    for (int i = 0; i < count; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1 - y * y), phi = 2.399963229728653 * i;
        const Vec3 n(r * std::cos(phi), y, r * std::sin(phi));
        const Vec3 p = center + radius * n;
        rows.push_back({p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
    }
    return rows;
}
}  // namespace

TEST(VariationalDescription, BlendKeepsTheConstraintsOutsideTheOtherOperands) {
    TemporaryFolder folder;
    CacheInFolder cache(folder);
    Json fields = {{"a", {{"type", "variational"}, {"normals", sphereNormals(Vec3(-0.5, 0, 0), 1.0, 120)}}},
                   {"b", {{"type", "variational"}, {"normals", sphereNormals(Vec3(0.5, 0, 0), 1.0, 120)}}},
                   {"v", {{"type", "variational"}, {"blend", {"a", "b"}}}}};
    const FieldLibrary library(fields, "/fields", folder.file("scene.json"), cache.options());
    const FieldProgram a = library.compile("a"), b = library.compile("b"), blend = library.compile("v");

    // Each kept constraint lies outside the other sphere and is interpolated;
    // a dropped one (well inside the other) is inside the blend.
    int kept = 0, dropped = 0;
    for (const auto& [own, other] : {std::pair{&fields["a"], &b}, std::pair{&fields["b"], &a}})
        for (const Json& row : (*own)["normals"]) {
            const Vec3 p(row[0], row[1], row[2]);
            if (other->value(p) > 0) {
                EXPECT_NEAR(blend.value(p), 0.0, 1e-8);
                ++kept;
            } else {
                // Near the crease the blend may round off a little; well
                // inside the other sphere it must be inside.
                if (other->value(p) < -0.05) {
                    EXPECT_LT(blend.value(p), 0.0);
                }
                ++dropped;
            }
        }
    EXPECT_GT(kept, 150);
    EXPECT_GT(dropped, 20);
    // No bulge: where the spheres meet, the blend stays near their union
    // (a function-sum blend swells there by a large fraction of the radius).
    double lo = 0.0, hi = 2.0;
    for (int i = 0; i < 60; ++i) (blend.value(Vec3(0, 0.5 * (lo + hi), 0)) < 0 ? lo : hi) = 0.5 * (lo + hi);
    const double unionCrossing = std::sqrt(1.0 - 0.25);  // the spheres' circle of intersection
    EXPECT_GT(lo, unionCrossing - 0.05);
    EXPECT_LT(lo, unionCrossing + 0.15);

    fields["v"]["blend"] = {"a", "v"};
    const std::string e = compileError(fields.dump());
    // Refused when the library is made, at the reference that closes it.
    EXPECT_NE(e.find("cycle in the field graph: v -> v"), std::string::npos) << e;
    EXPECT_NE(e.find("/fields/v/blend/1"), std::string::npos) << e;
    fields["v"]["blend"] = {"a", "ball"};
    EXPECT_NE(compileError(fields.dump()).find("unknown field \"ball\""), std::string::npos);
    fields["ball"] = {{"type", "sphere"}, {"radius", 1}};
    EXPECT_NE(compileError(fields.dump()).find("blend operands must be variational"), std::string::npos);
}

TEST(VariationalDescription, SampledFromAnotherField) {
    TemporaryFolder folder;
    CacheInFolder cache(folder);
    const FieldLibrary library(Json::parse(R"({"ring": {"type": "torus", "major": 1, "minor": 0.35},
        "v": {"type": "variational", "sample": "ring", "count": 300}})"), "/fields", folder.file("scene.json"),
                               cache.options());
    const FieldProgram torus = library.compile("ring"), v = library.compile("v");
    // The fit follows the torus it was sampled from, hole included.
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    int agree = 0, total = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p(u(rng), u(rng) * 0.4, u(rng));
        const double t = torus.value(p);
        if (std::abs(t) < 0.05) continue;  // near the surface the two may differ a little
        ++total;
        agree += (t < 0) == (v.value(p) < 0);
    }
    EXPECT_GE(agree, total - total / 100) << agree << " of " << total;
    EXPECT_GT(v.value(Vec3::Zero()), 0.0) << "the hole stays open";
}

// "solver": "partition" gives an MPU leaf of interpolants; its saved form
// (the MPU form, centres shared by index) loads bit-identically through
// {"type": "variational", "fitted": ...}, and damage names the place.
TEST(VariationalDescription, PartitionedFitsSaveLoadAndNameTheirDamage) {
    TemporaryFolder folder;
    const Json description = {{"type", "variational"}, {"solver", "partition"}, {"normals", sphereNormals(Vec3::Zero(), 1.0, 300)}};
    JsonObjectReader reader(description, "/fields/v", "scene.json");
    reader.string("type");
    VariationalContext context;
    const VariationalSource source = readVariationalSource(reader, context);
    ASSERT_TRUE(source.partitioned());
    PartitionReport report;
    const MpuField fitted = fitPartitionedVariationalField(source.constraints, &report);
    ASSERT_TRUE(fitted.hasInterpolants());
    const Json saved = mpuFieldToJson(fitted, partitionSummary(report), source.provenance, source.hash);
    std::ofstream(folder.file("fit.json")) << saved.dump();
    const FieldLibrary library(Json::parse(R"({"v": {"type": "variational", "fitted": "fit.json"}})"), "/fields",
                               folder.file("scene.json"));
    const FieldProgram loaded = library.compile("v");
    ASSERT_TRUE(std::holds_alternative<MpuLeafField>(loaded.singleLeaf()->shape));
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(-1.3, 1.3);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p(u(rng), u(rng), u(rng));
        ASSERT_EQ(loaded.value(p), fitted.value(p)) << "at " << p.transpose();
    }
    auto damaged = [&](auto&& change) {
        Json j = saved;
        change(j);
        try {
            mpuFieldFromJson(j, "saved.json");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(damaged([](Json& j) { j["interpolants"][2]["centers"][1] = 1u << 30; })
                  .find("saved.json: /interpolants/2/centers/1: expected an index"),
              std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["interpolants"][0]["weights"].erase(0); }).find("/interpolants/0/weights"),
              std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["positions"].erase(0); }).find("/positions"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["locals"][0][4] = 1u << 20; }).find("interpolant is out of range"), std::string::npos);
    EXPECT_NE(damaged([](Json& j) { j["interpolants"][1]["linear"] = "x"; }).find("/interpolants/1/linear"),
              std::string::npos);
}

TEST(VariationalDescription, SolverChoicesAreChecked) {
    const std::string normals = sphereNormals(Vec3::Zero(), 1.0, 40).dump();
    EXPECT_NE(compileError(R"({"v": {"type": "variational", "solver": "fast", "normals": )" + normals + "}}")
                  .find("scene.json: /fields/v/solver: unknown solver \"fast\""),
              std::string::npos);
    // Blends refit their operands' kept constraints densely: a partitioned operand is refused.
    const std::string blend = R"({"v": {"type": "variational", "blend": [
        {"type": "variational", "solver": "partition", "normals": )" + normals + R"(},
        {"type": "variational", "normals": )" + sphereNormals(Vec3(1, 0, 0), 1.0, 40).dump() + "}]}}";
    EXPECT_NE(compileError(blend).find("/fields/v/blend/0: blend operands are fitted by the dense solver"),
              std::string::npos) << compileError(blend);
}
