#include "geometry/meshing/cost_buckets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <random>

using namespace isotrace::geometry;

namespace {

struct Item {
    float cost;
    int id;
};

}  // namespace

// Pushes and pops interleaved at random against a reference: an ordered map
// from bucket to a first-in-first-out list. Every pop must give the oldest
// item of the lowest bucket, including after pushes below the last pop.
TEST(CostBuckets, PopsTheOldestItemOfTheLowestBucket) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> exponent(-40.0f, 40.0f);
    CostBuckets<Item> queue;
    std::map<uint32_t, std::deque<Item>> reference;
    int next = 0, popped = 0;
    for (int step = 0; step < 200000; ++step) {
        if (rng() % 3 != 0) {
            float cost;
            switch (rng() % 8) {
                case 0: cost = 0.0f; break;
                case 1: cost = std::numeric_limits<float>::infinity(); break;
                case 2: cost = std::numeric_limits<float>::denorm_min() * float(rng() % 100); break;
                default: cost = std::exp2(exponent(rng)); break;
            }
            const Item item{cost, next++};
            queue.push(item);
            reference[CostBuckets<Item>::bucketOf(cost)].push_back(item);
        } else {
            Item got{};
            const bool any = queue.pop(got);
            ASSERT_EQ(any, !reference.empty());
            if (!any) continue;
            auto lowest = reference.begin();
            ASSERT_EQ(got.id, lowest->second.front().id) << "step " << step;
            lowest->second.pop_front();
            if (lowest->second.empty()) reference.erase(lowest);
            ++popped;
        }
    }
    Item got{};
    while (queue.pop(got)) {
        ASSERT_FALSE(reference.empty());
        ASSERT_EQ(got.id, reference.begin()->second.front().id);
        reference.begin()->second.pop_front();
        if (reference.begin()->second.empty()) reference.erase(reference.begin());
    }
    EXPECT_TRUE(reference.empty());
    EXPECT_GT(popped, 50000);
}

// Buckets follow the order of costs and are narrow: costs 7% apart never
// share one; the last bucket is infinity's.
TEST(CostBuckets, BucketsAreOrderedAndAboutSixPercentWide) {
    using Buckets = CostBuckets<Item>;
    EXPECT_EQ(Buckets::bucketOf(0.0f), 0u);
    uint32_t previous = 0;
    for (float c = 1e-30f; c < 1e30f; c *= 1.07f) {
        const uint32_t b = Buckets::bucketOf(c);
        EXPECT_GT(b, previous) << c;
        previous = b;
    }
    EXPECT_GT(Buckets::bucketOf(std::numeric_limits<float>::infinity()), Buckets::bucketOf(3e38f));
}
