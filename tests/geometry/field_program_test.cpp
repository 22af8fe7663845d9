#include "geometry/field_program.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "geometry/fields/revolved_profile.h"
#include "support/field_catalog.h"

using namespace isotrace::geometry;
using isotrace::testing::CatalogEntry;
using isotrace::testing::compileCatalogEntry;
using isotrace::testing::fieldCatalog;

namespace {

Vec3 randomPointIn(const Box3& box, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
}

// A random box inside `region`, from large to tiny.
Box3 randomBox(const Box3& region, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double size = std::pow(10.0, -3.0 * u(rng)) * region.extent().maxCoeff() * 0.5;
    const Vec3 c = randomPointIn(region, rng);
    const Vec3 half(size * (0.2 + u(rng)), size * (0.2 + u(rng)), size * (0.2 + u(rng)));
    return {c - half, c + half};
}

Box3 testRegion(const FieldProgram& f) {
    const Box3 b = f.bounds();
    return b.isFinite() ? b.expanded(0.5) : Box3::around(Vec3::Zero(), 2.0);
}

class EveryField : public ::testing::TestWithParam<CatalogEntry> {};

Vec3 centralDifference(const FieldProgram& field, const Vec3& p, double h) {
    Vec3 fd;
    for (int k = 0; k < 3; ++k) {
        Vec3 d = Vec3::Zero();
        d[k] = h;
        fd[k] = (field.value(p + d) - field.value(p - d)) / (2 * h);
    }
    return fd;
}

}  // namespace

// For random boxes and random point pairs inside them, f stays inside the
// box's range and |f(a) - f(b)| <= L(box) |a - b|.
TEST_P(EveryField, RangeAndLipschitzBoundsAreSound) {
    const FieldProgram field = compileCatalogEntry(GetParam());
    const Box3 region = testRegion(field);
    for (int trial = 0; trial < 400; ++trial) {
        std::mt19937_64 rng(1000 + trial);
        const Box3 box = randomBox(region, rng);
        const BoxEstimate e = field.estimate(box);
        for (int pair = 0; pair < 25; ++pair) {
            const Vec3 a = randomPointIn(box, rng), b = randomPointIn(box, rng);
            const double fa = field.value(a), fb = field.value(b);
            ASSERT_TRUE(e.range.contains(fa)) << "trial " << trial << " box " << box << " f(a)=" << fa
                                              << " range " << e.range;
            ASSERT_LE(std::abs(fa - fb), e.lipschitz * (a - b).norm() * (1 + 1e-9) + 1e-12)
                << "trial " << trial << " box " << box << " L=" << e.lipschitz;
        }
    }
}

// The analytic gradient agrees with central differences away from kinks.
TEST_P(EveryField, GradientMatchesFiniteDifferences) {
    const FieldProgram field = compileCatalogEntry(GetParam());
    const Box3 region = testRegion(field);
    std::mt19937_64 rng(42);
    int agreeing = 0, total = 0;
    for (int i = 0; i < 400; ++i) {
        const Vec3 p = randomPointIn(region, rng);
        Vec3 g;
        field.valueAndGradient(p, g);
        const Vec3 fd = centralDifference(field, p, 1e-6);
        ++total;
        if ((fd - g).norm() <= 1e-4 * std::max(1.0, g.norm())) ++agreeing;
    }
    // Kinks of min/max and of distance fields are a measure-zero set; a few
    // samples may fall within h of one.
    EXPECT_GE(agreeing, total - 4) << GetParam().name;
}

// On the surface, where sphere tracing leaves its hits, the gradient points
// outward: shading and shadow-ray offsets depend on it. Roots are found by
// bisection to the last bit, the hardest case (the field's value there is
// rounding noise of either sign).
TEST_P(EveryField, GradientPointsOutwardOnTheSurface) {
    const FieldProgram field = compileCatalogEntry(GetParam());
    const Box3 region = testRegion(field);
    std::mt19937_64 rng(7);
    int roots = 0, inward = 0;
    for (int attempt = 0; attempt < 4000 && roots < 300; ++attempt) {
        Vec3 a = randomPointIn(region, rng), b = randomPointIn(region, rng);
        double fa = field.value(a), fb = field.value(b);
        if (!(fa > 0 && fb < 0)) continue;
        for (int i = 0; i < 200; ++i) {
            const Vec3 m = 0.5 * (a + b);
            if (m == a || m == b) break;
            (field.value(m) > 0 ? a : b) = m;
        }
        Vec3 g;
        field.valueAndGradient(a, g);
        const Vec3 fd = centralDifference(field, a, 1e-5);
        ++roots;
        if (g.dot(fd) < 0) ++inward;
    }
    // Near a kink the two may disagree; a flipped normal on a smooth face
    // shows up at many roots.
    EXPECT_LE(inward, 2) << GetParam().name << ": " << inward << " of " << roots << " roots";
}

// Points exactly on a cylinder's side (hypot(x, z) == r to the last bit) are
// where the distance to the side edge is pure rounding noise; the gradient
// must still be the outward normal, not the noise's direction.
TEST(RevolvedProfile, GradientOnTheSideIsTheOutwardNormal) {
    const RevolvedProfileField cylinder = RevolvedProfileField::cylinder(Vec3::Zero(), 0.2, 3.0);
    int onSurface = 0, wrong = 0;
    for (int i = 0; i < 20000; ++i) {
        const double angle = 0.3 + 2.0 * (i % 97) / 97.0, y = -1.4 + 2.8 * i / 20000.0;
        const Vec3 p(0.2 * std::cos(angle), y, 0.2 * std::sin(angle));
        if (std::hypot(p.x(), p.z()) != 0.2) continue;
        ++onSurface;
        Vec3 g;
        cylinder.valueAndGradient(p, g);
        if (g.dot(Vec3(p.x(), 0, p.z()) / 0.2) < 0.999) ++wrong;
    }
    EXPECT_GT(onSurface, 1000);
    EXPECT_EQ(wrong, 0) << "of " << onSurface;
}

// A cell's pruned program equals the whole field inside the cell.
TEST_P(EveryField, PrunedProgramEqualsFieldInsideItsBox) {
    const FieldProgram field = compileCatalogEntry(GetParam());
    const Box3 region = testRegion(field);
    for (int trial = 0; trial < 100; ++trial) {
        std::mt19937_64 rng(5000 + trial);
        const Box3 box = randomBox(region, rng);
        const FieldProgram pruned = field.prunedTo(box);
        ASSERT_LE(pruned.instructionCount(), field.instructionCount());
        for (int i = 0; i < 20; ++i) {
            const Vec3 p = randomPointIn(box, rng);
            ASSERT_NEAR(pruned.value(p), field.value(p), 1e-12 * std::max(1.0, std::abs(field.value(p))))
                << "trial " << trial << " box " << box;
        }
    }
}

namespace {
void collectTypes(const Json& j, std::set<std::string>& types) {
    if (j.is_object() && j.contains("type") && j["type"].is_string()) types.insert(j["type"].get<std::string>());
    if (j.is_structured())
        for (const Json& child : j) collectTypes(child, types);
}
}  // namespace

// The property tests above run over the catalog: a field type missing from
// it would escape them.
TEST(FieldCatalog, CoversEveryRegisteredFieldType) {
    std::set<std::string> used;
    collectTypes(Json::parse(isotrace::testing::kCatalogLibrary), used);
    for (const CatalogEntry& e : fieldCatalog()) collectTypes(Json::parse(e.json), used);
    for (const std::string& type : FieldLibrary::typeNames())
        EXPECT_TRUE(used.count(type)) << "field type \"" << type << "\" has no entry in tests/support/field_catalog.h";
}

INSTANTIATE_TEST_SUITE_P(Catalog, EveryField, ::testing::ValuesIn(fieldCatalog()),
                         [](const auto& info) { return info.param.name; });

// Inside (f < 0) and outside of union, intersection and difference follow
// the truth tables of their operands.
TEST(FieldProgramCsg, InsideOutsideFollowsTruthTables) {
    FieldProgram a, b, u, i, d;
    const SphereField s1{Vec3(-0.3, 0, 0), 0.7}, s2{Vec3(0.4, 0.1, 0), 0.6};
    a.addLeaf(s1);
    b.addLeaf(s2);
    {
        const uint32_t x = u.addLeaf(s1), y = u.addLeaf(s2);
        u.addBinary(FieldOp::Min, x, y);
    }
    {
        const uint32_t x = i.addLeaf(s1), y = i.addLeaf(s2);
        i.addBinary(FieldOp::Max, x, y);
    }
    {
        const uint32_t x = d.addLeaf(s1), y = d.addLeaf(s2);
        d.addBinary(FieldOp::Max, x, d.addUnary(FieldOp::Negate, y));
    }
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> c(-1.5, 1.5);
    for (int k = 0; k < 5000; ++k) {
        const Vec3 p(c(rng), c(rng), c(rng));
        const bool inA = a.value(p) < 0, inB = b.value(p) < 0;
        ASSERT_EQ(u.value(p) < 0, inA || inB) << p.transpose();
        ASSERT_EQ(i.value(p) < 0, inA && inB) << p.transpose();
        ASSERT_EQ(d.value(p) < 0, inA && !inB) << p.transpose();
    }
}

TEST(FieldProgramPruning, DropsOperandsThatCannotMatter) {
    FieldProgram f;
    const uint32_t x = f.addLeaf(SphereField{Vec3(-2, 0, 0), 0.5});
    const uint32_t y = f.addLeaf(SphereField{Vec3(2, 0, 0), 0.5});
    f.addBinary(FieldOp::Min, x, y);
    const FieldProgram near = f.prunedTo(Box3::around(Vec3(-2, 0, 0), 0.6));
    EXPECT_EQ(near.instructionCount(), 1u);
    const FieldProgram middle = f.prunedTo(Box3::around(Vec3(0, 0, 0), 0.3));
    EXPECT_EQ(middle.instructionCount(), 3u);  // equidistant: both operands matter
}

TEST(FieldProgramPruning, BlobsOutsideTheirSupportAreDropped) {
    BlobbyField blobs;
    for (int i = 0; i < 100; ++i) blobs.blobs.push_back({Vec3(i, 0, 0), 0.8, 1.0});
    FieldProgram f;
    f.addLeaf(blobs);
    const FieldProgram pruned = f.prunedTo(Box3::around(Vec3(50, 0, 0), 0.25));
    EXPECT_EQ(pruned.evaluationCost(), 3u);  // blobs 49, 50, 51 reach the box
}
