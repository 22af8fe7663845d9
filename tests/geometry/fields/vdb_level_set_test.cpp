#include "geometry/fields/vdb_level_set.h"

#include <gtest/gtest.h>

#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/meshing/polygonizer.h"
#include "geometry/openvdb_library.h"
#include "support/compile_field.h"
#include "support/temporary_files.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;
using isotrace::testing::TemporaryFolder;

namespace {

// The field written as a level set of the given voxel size, read back as a
// vdb field.
FieldProgram roundTrip(const FieldProgram& truth, double voxelSize, const TemporaryFolder& folder) {
    PolygonizeOptions options;
    options.resolution = int(std::ceil(truth.bounds().extent().maxCoeff() / voxelSize));
    const Polygonization surface = polygonize(truth, options);
    LevelSetWriteOptions write;
    write.voxelSize = truth.bounds().extent().maxCoeff() / options.resolution;
    const std::string path = folder.file("field.vdb");
    openVdbLibrary().writeLevelSet(path, surface.mesh, write);
    return compileField(R"({"type": "vdb", "file": ")" + path + R"("})");
}

// Points on the true surface: random points pulled onto it by Newton steps.
std::vector<Vec3> pointsOnSurface(const FieldProgram& field, int count, std::mt19937_64& rng) {
    const Box3 box = field.bounds();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> points;
    while (int(points.size()) < count) {
        Vec3 p = box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
        for (int step = 0; step < 30; ++step) {
            Vec3 g;
            const double f = field.valueAndGradient(p, g);
            if (g.squaredNorm() < 1e-12) break;
            p -= f * g / g.squaredNorm();
        }
        if (std::abs(field.value(p)) < 1e-10 && box.contains(p)) points.push_back(p);
    }
    return points;
}

double voxelSizeOf(const FieldProgram& vdb) {
    return std::get<VdbLevelSetField>(vdb.leaf(0).shape).levelSet->voxelSize();
}

}  // namespace

// Near a sphere, the level set holds the signed distance within half a voxel.
TEST(VdbLevelSet, SphereReadsBackAsItsDistanceWithinHalfAVoxel) {
    TemporaryFolder folder;
    const FieldProgram truth = compileField(R"({"type": "sphere", "center": [0.1, 0, -0.2], "radius": 0.8})");
    const FieldProgram vdb = roundTrip(truth, 0.04, folder);
    const double h = voxelSizeOf(vdb);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0;
    int tested = 0;
    while (tested < 2000) {
        const Vec3 p = Vec3(0.1, 0, -0.2) + Vec3(u(rng), u(rng), u(rng));
        const double d = truth.value(p);
        if (std::abs(d) > 2 * h) continue;  // the band's inner part: past it, values are clamped
        worst = std::max(worst, std::abs(vdb.value(p) - d));
        ++tested;
    }
    EXPECT_LT(worst, 0.5 * h);
    // Beyond the band, the background: positive outside, negative inside.
    EXPECT_FLOAT_EQ(vdb.value(Vec3(0.1, 0, -0.2)), -3 * float(h));
    EXPECT_FLOAT_EQ(vdb.value(Vec3(5, 5, 5)), 3 * float(h));
}

// Fields that are not distances get true distances: on the surfaces of the
// tangle and of a CSG part, the level set is within half a voxel of zero.
TEST(VdbLevelSet, TangleAndCsgPartReadBackWithinHalfAVoxelOfTheirSurfaces) {
    const std::pair<const char*, const char*> fields[] = {
        {"tangle", R"({"type": "polynomial", "preset": "tangle"})"},
        {"csg part", R"({"type": "difference", "of": [{"type": "box", "size": [1.6, 1.0, 1.2], "rounding": 0.05},
            {"type": "cylinder", "radius": 0.3, "height": 3}, {"type": "sphere", "center": [0.8, 0.5, 0.6], "radius": 0.5}]})"},
    };
    for (const auto& [name, json] : fields) {
        TemporaryFolder folder;
        const FieldProgram truth = compileField(json);
        const FieldProgram vdb = roundTrip(truth, truth.bounds().extent().maxCoeff() / 96, folder);
        const double h = voxelSizeOf(vdb);
        std::mt19937_64 rng(11);
        double worst = 0;
        for (const Vec3& p : pointsOnSurface(truth, 2000, rng)) worst = std::max(worst, std::abs(vdb.value(p)));
        EXPECT_LT(worst, 0.5 * h) << name;
    }
}

// Far from the band the proven range is the background alone, so the
// tracer skips it, and its gradient bound is 0.
TEST(VdbLevelSet, BeyondTheBandTheBoundsAreTheBackground) {
    const FieldProgram vdb = compileField(R"({"type": "vdb", "file": ")" ISOTRACE_TEST_DATA_DIR R"(/torus.vdb"})");
    const auto& levelSet = *std::get<VdbLevelSetField>(vdb.leaf(0).shape).levelSet;
    const double background = levelSet.background();
    const Box3 far(Vec3(3, 3, 3), Vec3(4, 5, 6));
    EXPECT_EQ(levelSet.range(far).lo, background);
    EXPECT_EQ(levelSet.range(far).hi, background);
    EXPECT_EQ(levelSet.lipschitz(far), 0.0);
    // The tube's axis, 0.3 deep, at the band's inner edge (0.24 deep).
    EXPECT_LT(levelSet.value(Vec3(0.9, 0, 0)), -0.95 * background);
    EXPECT_GE(levelSet.value(Vec3(0.9, 0, 0)), -background);
    // A box across the tube holds both signs and a slope near 1.
    const Box3 across = Box3::around(Vec3(0.9, 0, 0), 0.35);
    EXPECT_TRUE(levelSet.range(across).containsZero());
    EXPECT_GT(levelSet.lipschitz(across), 0.9);
    EXPECT_LT(levelSet.lipschitz(across), 2.0);
}

// The bounds hold the voxels' trilinear interpolant, with the metadata
// isotrace wrote: a hand-check of the reader against OpenVDB's own reading.
TEST(VdbLevelSet, ReadsTheGridItWasAskedFor) {
    const std::string file = ISOTRACE_TEST_DATA_DIR "/torus.vdb";
    const LevelSetGridData grid = openVdbLibrary().readLevelSet(file, "surface", 64 << 20);
    EXPECT_NEAR(grid.voxelSize, 0.08, 1e-12);
    EXPECT_NEAR(grid.background, 0.24, 1e-6);
    EXPECT_GT(grid.activeVoxels, 5000u);
    EXPECT_EQ(grid.metadata.at("isotrace:field"), "torus");
    EXPECT_THROW(openVdbLibrary().readLevelSet(file, "density", 64 << 20), std::runtime_error);
    EXPECT_THROW(openVdbLibrary().readLevelSet(file, "surface", 1000), std::runtime_error);
    // The surface's blocks keep their voxels, as OpenVDB holds them.
    size_t kept = 0;
    for (uint32_t f : grid.footprintOf) kept += f != kNoFootprint;
    EXPECT_EQ(grid.footprints.size(), kept * kFootprintVoxels);
    EXPECT_GT(kept, 0u);
    for (size_t b = 0; b < grid.blocks.size(); ++b) {
        if (grid.footprintOf[b] == kNoFootprint) continue;
        const int x = int(b % grid.blockCount[0]), y = int(b / grid.blockCount[0] % grid.blockCount[1]),
                  z = int(b / (size_t(grid.blockCount[0]) * grid.blockCount[1]));
        float corners[8];
        const int i = 8 * (grid.blockOrigin[0] + x) + 3, j = 8 * (grid.blockOrigin[1] + y) + 5, k = 8 * (grid.blockOrigin[2] + z) + 7;
        grid.voxels->cellCorners(i, j, k, corners);
        const float* footprint = grid.footprints.data() + size_t(grid.footprintOf[b]) * kFootprintVoxels;
        for (int c = 0; c < 8; ++c)
            ASSERT_EQ(corners[c], footprint[((7 + (c >> 2)) * kFootprintSide + 5 + (c >> 1 & 1)) * kFootprintSide + 3 + (c & 1)]);
    }
}
