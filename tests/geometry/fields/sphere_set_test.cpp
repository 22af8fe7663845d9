// Sphere sets (geometry/fields/sphere_set.h) against their definitions:
// minimum, maximum and a smooth union folded in increasing order; pruned
// copies equal to the whole set inside their boxes; and a scatter of
// thousands of spheres traced through the octree against the closed-form
// ray-sphere distances.
#include "geometry/fields/sphere_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "geometry/description/field_parser.h"
#include "geometry/smooth_min.h"
#include "geometry/tracing/implicit_surface.h"
#include "support/temporary_files.h"

using namespace isotrace::geometry;

namespace {

SphereSetField randomSet(SetOperation operation, int count, uint32_t seed, double blend = 0.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<SphereField> spheres;
    for (int i = 0; i < count; ++i) spheres.push_back({Vec3(u(rng), u(rng), u(rng)), 0.1 + 0.1 * (u(rng) + 1)});
    return SphereSetField::of(std::move(spheres), operation, blend);
}

// The definitions, with every sphere evaluated and nothing skipped.
double bruteForce(const SphereSetField& set, const Vec3& p) {
    std::vector<double> d;
    for (size_t i = 0; i < set.members.size(); ++i) d.push_back(set.sphere(i).value(p));
    std::sort(d.begin(), d.end());
    if (set.operation == SetOperation::Union) return d.front();
    if (set.operation == SetOperation::Intersection) return d.back();
    double partial = d[0];
    for (size_t i = 1; i < d.size(); ++i) partial = smoothMin(partial, d[i], set.blend).value;
    return partial;
}

Box3 randomBox(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.2, 1.2), size(0.02, 0.5);
    const Vec3 lower(u(rng), u(rng), u(rng));
    return {lower, lower + Vec3::Constant(size(rng))};
}

Vec3 pointIn(const Box3& box, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
}

}  // namespace

TEST(SphereSet, ValuesFollowTheDefinitionsWhateverTheOrder) {
    for (const SetOperation operation : {SetOperation::Union, SetOperation::SmoothUnion, SetOperation::Intersection}) {
        const SphereSetField set = randomSet(operation, 60, 3, 0.15);
        SphereSetField shuffled = set;
        std::shuffle(shuffled.members.begin(), shuffled.members.end(), std::mt19937(9));
        std::mt19937 rng(4);
        std::uniform_real_distribution<double> u(-1.3, 1.3);
        for (int i = 0; i < 500; ++i) {
            const Vec3 p(u(rng), u(rng), u(rng));
            EXPECT_NEAR(set.value(p), bruteForce(set, p), 1e-12);
            EXPECT_NEAR(shuffled.value(p), set.value(p), 1e-12);
            Vec3 gradient;
            EXPECT_NEAR(set.valueAndGradient(p, gradient), set.value(p), 1e-12);
            // The gradient against central differences, away from the kinks
            // of a hard union or intersection.
            const double h = 1e-6;
            Vec3 numeric;
            for (int k = 0; k < 3; ++k) {
                const Vec3 e = Vec3::Unit(k) * h;
                numeric[k] = (set.value(p + e) - set.value(p - e)) / (2 * h);
            }
            if (operation == SetOperation::SmoothUnion) {
                EXPECT_LT((gradient - numeric).norm(), 1e-5) << p.transpose();
            }
            EXPECT_LE(gradient.norm(), 1.0 + 1e-12);
        }
    }
}

TEST(SphereSet, PrunedCopiesAreExactInTheirBoxesAndRangesHoldTheValues) {
    for (const SetOperation operation : {SetOperation::Union, SetOperation::SmoothUnion, SetOperation::Intersection}) {
        const SphereSetField set = randomSet(operation, 300, 5, 0.1);
        std::mt19937 rng(6);
        size_t kept = 0;
        for (int b = 0; b < 200; ++b) {
            const Box3 box = randomBox(rng);
            const SphereSetField pruned = set.prunedTo(box);
            ASSERT_FALSE(pruned.members.empty());
            kept += pruned.members.size();
            const Interval range = set.range(box);
            for (int i = 0; i < 20; ++i) {
                const Vec3 p = pointIn(box, rng);
                EXPECT_EQ(pruned.value(p), set.value(p));
                EXPECT_GE(set.value(p), range.lo);
                EXPECT_LE(set.value(p), range.hi);
            }
        }
        // Small boxes keep a few spheres of the 300, not all.
        if (operation != SetOperation::Intersection) {
            EXPECT_LT(kept / 200.0, 40.0);
        }
        // Outside the bounds the field is positive.
        const Box3 bounds = set.bounds();
        for (int i = 0; i < 200; ++i) {
            const Vec3 p = bounds.center() + Vec3::Random().normalized() * (bounds.halfDiagonal() + 0.01);
            EXPECT_GT(set.value(p), 0.0);
        }
    }
}

// Large sets find their spheres through the hierarchy: the same ranges
// and the same pruned members as testing every sphere, to the bit, for
// boxes of every size, near and far, and for subsets already pruned.
TEST(SphereSet, HierarchyGivesExactlyWhatTestingEverySphereGives) {
    for (const SetOperation operation : {SetOperation::Union, SetOperation::SmoothUnion}) {
        const SphereSetField indexed = randomSet(operation, 40000, 21, 0.02);
        ASSERT_TRUE(indexed.hierarchy);
        SphereSetField linear = indexed;
        linear.hierarchy.reset();
        std::mt19937 rng(22);
        std::uniform_real_distribution<double> u(-1.5, 1.5), size(0.2, 2.0);
        size_t visitedBoxes = 0;
        for (int b = 0; b < 100; ++b) {
            const Vec3 lower(u(rng), u(rng), u(rng));
            const Box3 box(lower, lower + Vec3(size(rng), size(rng), size(rng)));
            const Interval a = indexed.range(box), e = linear.range(box);
            EXPECT_EQ(a.lo, e.lo) << box;
            EXPECT_EQ(a.hi, e.hi) << box;
            const SphereSetField pruned = indexed.prunedTo(box), expected = linear.prunedTo(box);
            EXPECT_EQ(pruned.members, expected.members) << box;
            // A child of a large pruned copy, through the hierarchy again.
            if (pruned.members.size() > 4096) {
                ++visitedBoxes;
                SphereSetField prunedLinear = pruned;
                prunedLinear.hierarchy.reset();
                const Box3 child = box.octant(b % 8);
                EXPECT_EQ(pruned.prunedTo(child).members, prunedLinear.prunedTo(child).members);
                EXPECT_EQ(pruned.range(child).lo, prunedLinear.range(child).lo);
                EXPECT_EQ(pruned.range(child).hi, prunedLinear.range(child).hi);
                // Past its box the copy's list is all it has: it tests its
                // members, as the linear copy does.
                const Box3 wider = box.expanded(0.1);
                EXPECT_EQ(pruned.range(wider).lo, prunedLinear.range(wider).lo);
                EXPECT_EQ(pruned.prunedTo(wider).members, prunedLinear.prunedTo(wider).members);
            }
        }
        EXPECT_GT(visitedBoxes, 10u);
    }
}

// Rays from outside every sphere meet a union first where they enter the
// nearest sphere along them: |o + t d - c| = r in closed form.
TEST(SphereSet, ScatteredUnionTracesToTheClosedFormHits) {
    const Json library = Json::parse(R"({"foam": {"type": "scatter", "count": 3000, "seed": 11,
        "region": [[-2, -2, -2], [2, 2, 2]], "shape": {"type": "sphere", "radius": 0.08}, "scale": [0.5, 1.5]}})");
    FieldLibrary fields(library, "/fields", "test");
    FieldProgram program = fields.compile("foam");
    const auto& set = std::get<SphereSetField>(program.leaf(0).shape);
    ASSERT_EQ(set.members.size(), 3000u);
    const ImplicitSurface surface(std::move(program));
    // The octree refined until a ray meets at most 128 spheres per cell:
    // those reaching into it, fewer than its program holds (the spheres
    // that decide the value there).
    EXPECT_GT(surface.cells().size(), 20u);
    size_t largest = 0, reachingTotal = 0, heldTotal = 0;
    for (const SurfaceCell& cell : surface.cells()) {
        EXPECT_GT(cell.payload.termCount, 0u);
        largest = std::max<size_t>(largest, cell.payload.termCount);
        reachingTotal += cell.payload.termCount;
        heldTotal += surface.cellProgram(cell).evaluationCost();
    }
    EXPECT_LE(largest, 128u);
    EXPECT_LT(reachingTotal, heldTotal);
    // Every cell is solved in closed form, by one tracer.
    EXPECT_EQ(surface.acceleratedCellCount(), surface.cells().size());
    EXPECT_EQ(surface.tracerCount(), 1u);

    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0;
    for (int i = 0; i < 400; ++i) {
        const Vec3 origin = Vec3(u(rng), u(rng), u(rng)).normalized() * 4.0;
        const Vec3 direction = (Vec3(u(rng), u(rng), u(rng)) * 1.5 - origin).normalized();
        double nearest = std::numeric_limits<double>::infinity();
        for (const SphereField& s : *set.all) {
            const Vec3 oc = origin - s.center;
            const double b = oc.dot(direction), c = oc.squaredNorm() - s.radius * s.radius;
            if (b * b - c < 0) continue;
            const double t = -b - std::sqrt(b * b - c);
            if (t > 0) nearest = std::min(nearest, t);
        }
        const TraceResult r = surface.intersect(origin, direction, 0.0, 100.0);
        ASSERT_EQ(r.hit, std::isfinite(nearest)) << "ray " << i;
        if (!r.hit) continue;
        ++hits;
        EXPECT_NEAR(r.t, nearest, 1e-5) << "ray " << i;
    }
    EXPECT_GT(hits, 100);
}

TEST(SphereSet, ScatterIsTheSameOnEveryRunAndStaysInItsRegion) {
    const Json library = Json::parse(R"({"a": {"type": "scatter", "count": 100, "seed": 3, "operation": "smooth_union",
        "radius": 0.05, "region": [[0, 0, 0], [1, 2, 3]], "shape": {"type": "sphere", "radius": 0.1}}})");
    FieldLibrary first(library, "/fields", "test"), second(library, "/fields", "test");
    const FieldProgram a = first.compile("a"), b = second.compile("a");
    const auto& sa = std::get<SphereSetField>(a.leaf(0).shape);
    const auto& sb = std::get<SphereSetField>(b.leaf(0).shape);
    ASSERT_EQ(sa.members.size(), 100u);
    EXPECT_EQ(sa.operation, SetOperation::SmoothUnion);
    EXPECT_EQ(sa.blend, 0.05);
    for (size_t i = 0; i < sa.members.size(); ++i) {
        EXPECT_EQ(sa.sphere(i).center, sb.sphere(i).center);
        EXPECT_TRUE(Box3(Vec3(0, 0, 0), Vec3(1, 2, 3)).contains(sa.sphere(i).center));
        EXPECT_EQ(sa.sphere(i).radius, 0.1);
    }
}

// An operand list read from PLY: ASCII with a radius column and other
// columns beside it, binary little-endian without one (the shape's radius),
// the same spheres either way.
TEST(SphereSet, ScatterReadsSpheresFromPlyFiles) {
    isotrace::testing::TemporaryFolder folder;
    folder.write("ascii.ply", "ply\nformat ascii 1.0\ncomment three spheres\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nproperty uchar red\nproperty double radius\n"
                              "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
                              "0 0 0 255 0.5\n1.5 0 0 0 0.25\n-1 2 0.5 7 1\n");
    std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property double z\nend_header\n";
    for (const auto& [x, y, z] : {std::array<double, 3>{0, 0, 0}, {1.5, 0, 0}, {-1, 2, 0.5}}) {
        const float xy[2] = {float(x), float(y)};
        binary.append(reinterpret_cast<const char*>(xy), sizeof(xy));
        binary.append(reinterpret_cast<const char*>(&z), sizeof(z));
    }
    folder.write("binary.ply", binary);
    const Json library = Json::parse(R"({"ascii": {"type": "scatter", "file": "ascii.ply"},
        "binary": {"type": "scatter", "file": "binary.ply", "shape": {"type": "sphere", "radius": 0.3}}})");
    FieldLibrary fields(library, "/fields", folder.file("scene.json"));
    const FieldProgram ascii = fields.compile("ascii"), binaryProgram = fields.compile("binary");
    const auto& a = std::get<SphereSetField>(ascii.leaf(0).shape);
    const auto& b = std::get<SphereSetField>(binaryProgram.leaf(0).shape);
    ASSERT_EQ(a.members.size(), 3u);
    ASSERT_EQ(b.members.size(), 3u);
    // The union's value at points against the spheres written.
    const std::vector<SphereField> written = {{Vec3(0, 0, 0), 0.5}, {Vec3(1.5, 0, 0), 0.25}, {Vec3(-1, 2, 0.5), 1}};
    for (const Vec3& p : {Vec3(0.2, 0.1, 0), Vec3(1.6, 0, 0.1), Vec3(-1, 1.5, 0.4), Vec3(3, 3, 3)}) {
        double expected = std::numeric_limits<double>::infinity(), expectedBinary = expected;
        for (const SphereField& s : written) {
            expected = std::min(expected, s.value(p));
            expectedBinary = std::min(expectedBinary, (p - s.center).norm() - 0.3);
        }
        EXPECT_NEAR(a.value(p), expected, 1e-6);
        EXPECT_NEAR(b.value(p), expectedBinary, 1e-6);
    }
}
