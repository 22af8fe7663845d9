#include "geometry/tracing/implicit_surface.h"

#include <cmath>

#include <gtest/gtest.h>

#include "support/compile_field.h"
#include "support/embree_scene.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(ImplicitSurface, KeepsOnlyCellsThatMayHoldSurface) {
    // Split as deep as the octree goes (by default a distance field's cells
    // stop at depth 1: see ImplicitSurfaceOptions::distanceCellDepth), and
    // marched: the torus accelerator would take the bare torus as one cell.
    ImplicitSurfaceOptions deep;
    deep.distanceCellDepth = deep.maxDepth;
    deep.cellAccelerators.clear();
    ImplicitSurface surface(compileField(R"({"type": "torus", "major": 1, "minor": 0.3})"), deep);
    ASSERT_FALSE(surface.cells().empty());
    for (const SurfaceCell& cell : surface.cells()) {
        EXPECT_TRUE(surface.field().estimate(cell.box).range.containsZero());
        EXPECT_LE(cell.lipschitz, surface.globalLipschitz() * (1 + 1e-9));
    }
    // A torus' cells cover far less than its bounding box.
    double cellVolume = 0;
    for (const SurfaceCell& cell : surface.cells()) cellVolume += cell.box.extent().prod();
    EXPECT_LT(cellVolume, 0.5 * surface.bounds().extent().prod());
}

// A distance field's cells stop splitting at distanceCellDepth (two
// primitives combined one level deeper); other fields refine on. Marched:
// the sphere accelerator would take the bare sphere as one cell.
TEST(ImplicitSurface, DistanceCellsStopAtTheirDepth) {
    const FieldProgram sphere = compileField(R"({"type": "sphere", "radius": 1})");
    const FieldProgram difference = compileField(R"({"type": "difference", "of": [
        {"type": "sphere", "radius": 1}, {"type": "sphere", "radius": 0.6, "center": [0.8, 0, 0]}]})");
    size_t previous = 0;
    for (int depth : {1, 2, 3}) {
        ImplicitSurfaceOptions options;
        options.distanceCellDepth = depth;
        options.cellAccelerators.clear();
        // At most the 8^depth cells of that level, and more at each level
        // (the sphere's surface crosses 8, 56, ... of them).
        const size_t one = ImplicitSurface(sphere, options).cells().size();
        EXPECT_LE(one, size_t(1) << (3 * depth)) << depth;
        EXPECT_GT(one, previous) << depth;
        previous = one;
        // The difference goes one level deeper than the sphere alone.
        const size_t two = ImplicitSurface(difference, options).cells().size();
        EXPECT_LE(two, size_t(1) << (3 * (depth + 1))) << depth;
        EXPECT_GT(two, one) << depth;
    }
}

// Refinement stops at the last level within the cell budget (the level
// over it is counted, never built).
TEST(ImplicitSurface, KeepsWithinTheCellBudget) {
    const FieldProgram torus = compileField(R"({"type": "torus", "major": 1, "minor": 0.3})");
    size_t previous = 0;
    for (size_t budget : {40, 400, 4000}) {
        ImplicitSurfaceOptions options;
        options.cellAccelerators.clear();  // one cell per octree cell, no parts
        options.distanceCellDepth = options.maxDepth;
        options.cellBudget = budget;
        const size_t cells = ImplicitSurface(torus, options).cells().size();
        EXPECT_LE(cells, budget);
        EXPECT_GT(cells, previous) << budget;
        previous = cells;
    }
}

TEST(ImplicitSurface, UnboundedFieldIsRefused) {
    EXPECT_THROW(ImplicitSurface(compileField(R"({"type": "plane"})")), std::invalid_argument);
}

// Goursat's tangle x^4 - 5x^2 + y^4 - 5y^2 + z^4 - 5z^2 + 11.8 = 0 reaches
// farthest along x where y^2 = z^2 = 2.5: x^2 = (5 + sqrt(27.8)) / 2.
// Sphere traced (no accelerator), the tangle is refined again from the box
// its first refinement proves; with its exact-root accelerator it is one
// cell, that box. Either way the farthest point is found.
TEST(ImplicitSurface, LooseDomainIsTightenedToTheProvenSurfaceBox) {
    const std::string tangle = R"({"type": "polynomial", "preset": "tangle", "domain": [[-3, -3, -3], [3, 3, 3]]})";
    ImplicitSurfaceOptions marchOnly;
    marchOnly.cellAccelerators.clear();
    const ImplicitSurface marched(compileField(tangle), marchOnly), solved(compileField(tangle));
    const double reach = std::sqrt((5 + std::sqrt(27.8)) / 2), side = std::sqrt(2.5);
    for (const ImplicitSurface* surface : {&marched, &solved}) {
        const Box3& root = surface->refinementRoot();
        EXPECT_LT(root.extent().maxCoeff(), 0.9 * 6);
        for (int sx : {-1, 1})
            EXPECT_TRUE(root.contains(Vec3(sx * reach, side, -side)));
        // The farthest point is still found, head on, from outside the tight box.
        const TraceResult hit = surface->intersect(Vec3(5, side, side), Vec3(-1, 0, 0), 0, 10);
        ASSERT_TRUE(hit.hit);
        EXPECT_NEAR(hit.t, 5 - reach, 1e-5);
    }
    // Marched cells hug the surface: their union reaches a little past it
    // (interval ranges of a quartic overestimate), far less than the
    // domain's 3.
    Box3 cells;
    for (const SurfaceCell& cell : marched.cells()) cells.extend(cell.box);
    EXPECT_LT(cells.upper.maxCoeff(), reach + 0.25);
    EXPECT_GT(cells.lower.minCoeff(), -reach - 0.25);
    // Solved, one cell within the proven box.
    ASSERT_EQ(solved.cells().size(), 1u);
    EXPECT_LT(solved.cells()[0].box.upper.maxCoeff(), reach + 0.4);
    EXPECT_GT(solved.cells()[0].box.lower.minCoeff(), -reach - 0.4);
}

// A bare shape whose root along a ray is found exactly (sphere, ring torus,
// sharp box, polynomial) is one cell: its root costs the same in any box,
// and every further cell would cost a ray a call. A CSG tree keeps its
// octree cells, each with the tree pruned to what it holds.
TEST(ImplicitSurface, BareShapesWithExactRootsAreOneCell) {
    for (const char* bare : {R"({"type": "sphere", "radius": 1})", R"({"type": "torus", "major": 1, "minor": 0.3})",
                             R"({"type": "box", "size": [1, 2, 3]})", R"({"type": "polynomial", "preset": "heart"})"})
        EXPECT_EQ(ImplicitSurface(compileField(bare)).cells().size(), 1u) << bare;
    const ImplicitSurface spindle(compileField(R"({"type": "torus", "major": 0.5, "minor": 0.6})"));
    EXPECT_GT(spindle.cells().size(), 1u);  // sphere traced: its quartic has an inner sheet
    // A rounded box's cells keep only the pieces (slabs, edge cylinders,
    // corner balls) that reach them.
    const ImplicitSurface rounded(compileField(R"({"type": "box", "size": [1, 2, 3], "rounding": 0.2})"));
    EXPECT_GT(rounded.cells().size(), 1u);
    const ImplicitSurface difference(compileField(R"({"type": "difference", "of": [
        {"type": "sphere", "radius": 1}, {"type": "sphere", "radius": 0.6, "center": [0.8, 0, 0]}]})"));
    EXPECT_GT(difference.cells().size(), 1u);
}

TEST(ImplicitSurface, TightDomainIsKept) {
    ImplicitSurface surface(compileField(R"({"type": "sphere", "radius": 1})"));
    EXPECT_LE((surface.refinementRoot().extent() - surface.bounds().extent()).cwiseAbs().maxCoeff(), 1e-3);
}

// A field that is a distance bound in a cell (Lipschitz 1: spheres, boxes,
// tori and their unions and differences) gains nothing from smaller cells,
// so such cells stop splitting at depth 3, or 4 for two primitives combined,
// while a field whose bound smaller cells tighten (Goursat's tangle, sphere
// traced here without its exact-root accelerator) refines further, to the
// depth its cell budget allows.
TEST(ImplicitSurface, DistanceBoundedCellsStopSplittingEarly) {
    auto smallestCellExtent = [](const ImplicitSurface& s) {
        double smallest = INFINITY;
        for (const SurfaceCell& c : s.cells()) smallest = std::min(smallest, c.box.extent().maxCoeff());
        return smallest;
    };
    // Shrinking to the surface takes a cell down by up to two halvings.
    const ImplicitSurface sphere(compileField(R"({"type": "sphere", "radius": 1})"));
    EXPECT_LE(sphere.cells().size(), 512u);
    EXPECT_GE(smallestCellExtent(sphere), sphere.refinementRoot().extent().maxCoeff() / 8 / 4 * (1 - 1e-9));
    const ImplicitSurface difference(compileField(R"({"type": "difference", "of": [{"type": "box", "size": [2, 2, 2]},
        {"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 1}]})"));
    EXPECT_GE(smallestCellExtent(difference), difference.refinementRoot().extent().maxCoeff() / 16 / 4 * (1 - 1e-9));
    ImplicitSurfaceOptions marchOnly;
    marchOnly.cellAccelerators.clear();
    const ImplicitSurface tangle(compileField(R"({"type": "polynomial", "preset": "tangle"})"), marchOnly);
    EXPECT_LT(smallestCellExtent(tangle), tangle.refinementRoot().extent().maxCoeff() / 8 / 4 * (1 - 1e-9));
}

// A CSG face that lies on the plane between two octree cells (a box cut
// from a sphere at its centre's planes, where the octree splits) belongs to
// neither cell's interior: each cell must still see the sign change there.
// Missed, a ray into the cut-away octant went on to the sphere's far side
// and was taken for one leaving the solid (issue #62: glass gained ior^2).
// Every ray into the cut corner must meet the cut faces, from the sphere
// tracer and from the closed-form CSG cells alike, with the face's normal.
TEST(ImplicitSurface, FacesOnCellBoundariesAreHit) {
    // In the large sphere the sphere is pruned from the cells by the cut's
    // faces, which leaves the carving box alone there; rays start inside the
    // cut-away box, at `start` from the face.
    struct Case {
        const char* field;
        double start;
    };
    for (const Case& c : {Case{R"({"type": "difference", "of": [{"type": "sphere", "radius": 1},
                                   {"type": "box", "center": [0.5, 0.5, 0.5], "size": [1, 1, 1]}]})", 4.0},
                          Case{R"({"type": "difference", "of": [{"type": "sphere", "radius": 3},
                                   {"type": "box", "center": [0.5, 0.5, 0.5], "size": [1, 1, 1]}]})", 0.5}})
        for (const bool accelerated : {true, false}) {
            ImplicitSurfaceOptions options;
            if (!accelerated) options.cellAccelerators.clear();
            ImplicitSurface surface(isotrace::testing::compileField(c.field), options);
            isotrace::testing::EmbreeScene scene;
            scene.attach(surface);
            scene.commit();
            for (const Vec3& target : {Vec3(0.3, 0.4, 0.0), Vec3(0.61, 0.2, 0.0), Vec3(0.1, 0.05, 0.0)}) {
                const isotrace::testing::EmbreeHit hit = scene.intersect(target + Vec3(0, 0, c.start), Vec3(0, 0, -1));
                ASSERT_TRUE(hit.hit) << target.transpose();
                EXPECT_NEAR(hit.t, c.start, 1e-5) << "accelerated " << accelerated << ", towards " << target.transpose();
                EXPECT_GT(hit.normal.normalized().z(), 0.99) << hit.normal.transpose();
            }
            // Along x into the face x = 0 of the cut.
            const isotrace::testing::EmbreeHit side = scene.intersect(Vec3(c.start, 0.3, 0.4), Vec3(-1, 0, 0));
            ASSERT_TRUE(side.hit);
            EXPECT_NEAR(side.t, c.start, 1e-5) << "accelerated " << accelerated;
        }
}

TEST(ImplicitSurface, RaysThroughAConcaveEdgeCrossNothingThere) {
    // The cut's faces x = 0 and y = 0 meet along the z axis, which is also
    // where octree cells meet. A ray from inside the solid through that
    // edge, from the quadrant x > 0, y < 0 to x < 0, y > 0, stays in the
    // solid: its first surface is the sphere, not the edge. The same ray
    // from the cut-away quadrant's side enters the solid at the edge.
    const char* field = R"({"type": "difference", "of": [{"type": "sphere", "radius": 1},
                           {"type": "box", "center": [0.5, 0.5, 0.5], "size": [1, 1, 1]}]})";
    for (const bool accelerated : {true, false}) {
        ImplicitSurfaceOptions options;
        if (!accelerated) options.cellAccelerators.clear();
        ImplicitSurface surface(isotrace::testing::compileField(field), options);
        isotrace::testing::EmbreeScene scene;
        scene.attach(surface);
        scene.commit();
        for (const double z : {0.2, 0.5, 0.8}) {
            for (const Vec3& across : {Vec3(-1, 1, 0), Vec3(-1, 1, 0.4), Vec3(-0.3, 1, -0.2)}) {
                const Vec3 d = across.normalized();
                const Vec3 origin = Vec3(0, 0, z) - 0.3 * d;
                const isotrace::testing::EmbreeHit hit = scene.intersect(origin, d);
                ASSERT_TRUE(hit.hit);
                const Vec3 p = origin + hit.t * d;
                EXPECT_NEAR(p.norm(), 1.0, 1e-4) << "accelerated " << accelerated << ", z " << z << ", hit at "
                                                 << p.transpose();
            }
        }
    }
}
