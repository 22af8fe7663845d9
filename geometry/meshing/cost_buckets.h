// A priority queue of non-negative float costs that is exact only to
// buckets: the cost's exponent and top four mantissa bits, so costs in one
// bucket differ by at most 6.25%, and leave it first in, first out.
//
// The simplifier pops millions of candidates, most of them stale; a binary
// heap pays a sift for every push and pop, here both are O(1). Within 6%, the
// order of collapses matters little to the result (on the polygonization
// bench, triangle counts within 1.5% of the heap's), and first in, first out
// spreads equal-cost collapses (a flat region's) over the region instead of
// piling them onto the newest vertex.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace isotrace::geometry {

/// Item has a `float cost`, non-negative (or +infinity, which comes last).
template <class Item>
class CostBuckets {
public:
    CostBuckets() : buckets_(kBuckets), heads_(kBuckets, 0) {}

    static uint32_t bucketOf(float cost) { return std::bit_cast<uint32_t>(cost) >> kShift; }

    void push(const Item& item) {
        const uint32_t b = bucketOf(item.cost);
        buckets_[b].push_back(item);
        nonEmpty_[b / 64] |= uint64_t(1) << (b % 64);
        lowestWord_ = std::min(lowestWord_, b / 64);
    }

    /// The oldest item of the lowest non-empty bucket; false when empty.
    bool pop(Item& out) {
        while (lowestWord_ < kWords && nonEmpty_[lowestWord_] == 0) ++lowestWord_;
        if (lowestWord_ == kWords) return false;
        const uint32_t b = lowestWord_ * 64 + uint32_t(std::countr_zero(nonEmpty_[lowestWord_]));
        std::vector<Item>& bucket = buckets_[b];
        out = bucket[heads_[b]++];
        if (heads_[b] == bucket.size()) {  // keeps its capacity for the next pushes
            bucket.clear();
            heads_[b] = 0;
            nonEmpty_[b / 64] &= ~(uint64_t(1) << (b % 64));
        }
        return true;
    }

    /// Drops every item; the buckets keep their capacity.
    void clear() {
        for (; lowestWord_ < kWords; ++lowestWord_) {
            for (uint64_t bits = nonEmpty_[lowestWord_]; bits != 0; bits &= bits - 1) {
                const uint32_t b = lowestWord_ * 64 + uint32_t(std::countr_zero(bits));
                buckets_[b].clear();
                heads_[b] = 0;
            }
            nonEmpty_[lowestWord_] = 0;
        }
    }

private:
    // Non-negative floats order as their bit patterns; +infinity is
    // 0x7f800000, the last bucket.
    static constexpr uint32_t kShift = 19;
    static constexpr uint32_t kBuckets = (0x7f800000u >> kShift) + 1;
    static constexpr uint32_t kWords = (kBuckets + 63) / 64;

    std::vector<std::vector<Item>> buckets_;
    std::vector<uint32_t> heads_;  ///< the next item to pop in each bucket
    uint64_t nonEmpty_[kWords] = {};
    uint32_t lowestWord_ = kWords;  ///< no non-empty bucket lies below this word
};

}  // namespace isotrace::geometry
