#include "renderer/memory_pages.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

namespace isotrace {
namespace {

// The process's resident memory in bytes (/proc/self/statm's second field).
size_t residentBytes() {
    std::ifstream statm("/proc/self/statm");
    size_t size = 0, resident = 0;
    statm >> size >> resident;
    return resident * size_t(sysconf(_SC_PAGESIZE));
}

TEST(MemoryPages, LargeFreedHeapGoesBackToTheKernel) {
    keepFreedMemoryForReuse();  // freed heap is kept up to 256 MB: nothing goes back by itself
    constexpr size_t kBlock = size_t(1) << 20, kBlocks = 128;  // heap blocks (below the 32 MB mmap limit)
    std::vector<void*> blocks;
    for (size_t i = 0; i < kBlocks; ++i) {
        blocks.push_back(std::malloc(kBlock));
        ASSERT_NE(blocks.back(), nullptr);
        std::memset(blocks.back(), 1, kBlock);
    }
    for (void* b : blocks) std::free(b);
    const size_t kept = residentBytes();
    releaseLargeFreedMemory();
    const size_t released = residentBytes();
    // At least three quarters of the 128 MB freed leave the process.
    EXPECT_GT(kept, released + kBlocks * kBlock * 3 / 4) << "kept " << kept << " B, then " << released << " B";
}

}  // namespace
}  // namespace isotrace
