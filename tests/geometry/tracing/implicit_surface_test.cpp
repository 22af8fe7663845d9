#include "geometry/tracing/implicit_surface.h"

#include <gtest/gtest.h>

#include "support/compile_field.h"

using namespace isotrace::geometry;
using isotrace::testing::compileField;

TEST(ImplicitSurface, KeepsOnlyCellsThatMayHoldSurface) {
    ImplicitSurface surface(compileField(R"({"type": "torus", "major": 1, "minor": 0.3})"));
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

TEST(ImplicitSurface, UnboundedFieldIsRefused) {
    EXPECT_THROW(ImplicitSurface(compileField(R"({"type": "plane"})")), std::invalid_argument);
}
