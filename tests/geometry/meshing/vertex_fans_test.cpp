#include "geometry/meshing/vertex_fans.h"

#include <gtest/gtest.h>

#include <numeric>
#include <vector>

using namespace isotrace::geometry;

namespace {

std::vector<uint32_t> listed(const VertexFans& fans, uint32_t v) {
    const std::span<const uint32_t> s = fans[v];
    return {s.begin(), s.end()};
}

}  // namespace

// A fan grows past the record's slots into a list of its own and shrinks
// back, keeping its faces and their order; other vertices' fans are untouched.
TEST(VertexFans, GrowsPastTheRecordAndShrinksBackInOrder) {
    VertexFans fans(3);
    const std::vector<uint32_t> small = {7, 3, 9};
    fans.assign(0, small);
    fans.assign(1, {});
    fans.assign(2, std::vector<uint32_t>{42});
    EXPECT_EQ(listed(fans, 0), small);
    EXPECT_TRUE(fans.empty(1));

    std::vector<uint32_t> expected = small;
    for (uint32_t f = 100; f < 130; ++f) {  // far past 15 faces
        fans.pushBack(0, f);
        expected.push_back(f);
        ASSERT_EQ(listed(fans, 0), expected) << "after pushing " << f;
    }
    // Dropping every face but a few moves the fan back into its record.
    fans.eraseIf(0, [](uint32_t f) { return f >= 100 && f % 10 != 0; });
    EXPECT_EQ(listed(fans, 0), (std::vector<uint32_t>{7, 3, 9, 100, 110, 120}));
    fans.pushBack(0, 5);
    EXPECT_EQ(listed(fans, 0), (std::vector<uint32_t>{7, 3, 9, 100, 110, 120, 5}));

    // A large fan assigned whole, erased in part while still large.
    std::vector<uint32_t> large(40);
    std::iota(large.begin(), large.end(), 0u);
    fans.assign(1, large);
    EXPECT_EQ(listed(fans, 1), large);
    fans.eraseIf(1, [](uint32_t f) { return f % 2 == 1; });
    std::vector<uint32_t> even;
    for (uint32_t f = 0; f < 40; f += 2) even.push_back(f);
    EXPECT_EQ(listed(fans, 1), even);

    fans.clear(1);
    EXPECT_TRUE(fans.empty(1));
    EXPECT_EQ(listed(fans, 2), (std::vector<uint32_t>{42}));
}
