// The executable's operator new (renderer/commands/large_allocations.cpp),
// linked into this test as into isotrace.
#include "renderer/commands/large_allocations.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <memory>
#include <new>
#include <sstream>
#include <string>

namespace isotrace {
namespace {

bool transparentHugePagesAvailable() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(in, modes);
    return in && modes.find("[never]") == std::string::npos;
}

// The VmFlags of the mapping holding `address`, from /proc/self/smaps.
std::string mappingFlags(const void* address) {
    std::ifstream smaps("/proc/self/smaps");
    const uintptr_t a = uintptr_t(address);
    bool inside = false;
    for (std::string line; std::getline(smaps, line);) {
        uintptr_t begin, end;
        char dash;
        std::istringstream range(line);
        if (line.find("VmFlags:") == 0) {
            if (inside) return line;
        } else if (range >> std::hex >> begin >> dash >> end && dash == '-' && line.find(':') > line.find(' ')) {
            inside = begin <= a && a < end;
        }
    }
    return "";
}

TEST(LargeAllocations, BlocksOfHugePagesAreAdvisedIntoThem) {
    if (!kHugePageOperatorNew) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
    if (!transparentHugePagesAvailable()) GTEST_SKIP() << "transparent huge pages are disabled here";
    constexpr size_t kBytes = size_t(8) << 20;
    std::unique_ptr<char[]> large(new char[kBytes]);
    // The middle of the block: its first and last pages may be shared with
    // the allocator's neighbours and are left alone.
    const std::string flags = mappingFlags(large.get() + kBytes / 2);
    ASSERT_NE(flags, "") << "no mapping holds the block";
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    large[kBytes / 2] = 1;  // usable
    EXPECT_EQ(large[kBytes / 2], 1);
}

TEST(LargeAllocations, OverAlignedBlocksAreAdvisedAndAligned) {
    if (!kHugePageOperatorNew) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
    if (!transparentHugePagesAvailable()) GTEST_SKIP() << "transparent huge pages are disabled here";
    struct alignas(64) Line {
        char bytes[64];
    };
    constexpr size_t kLines = (size_t(8) << 20) / sizeof(Line);
    std::unique_ptr<Line[]> large(new Line[kLines]);
    EXPECT_EQ(uintptr_t(large.get()) % 64, 0u);
    const std::string flags = mappingFlags(large.get() + kLines / 2);
    ASSERT_NE(flags, "") << "no mapping holds the block";
    EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    large[kLines / 2].bytes[0] = 1;
    EXPECT_EQ(large[kLines / 2].bytes[0], 1);
}

int handlerCalls = 0;
char* volatile escaped = nullptr;  // keeps the compiler from eliding new

TEST(LargeAllocations, AFailedAllocationCallsTheNewHandlerThenThrows) {
    if (!kHugePageOperatorNew) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
    handlerCalls = 0;
    // The handler frees nothing and removes itself: the next failure throws.
    std::set_new_handler([] {
        ++handlerCalls;
        std::set_new_handler(nullptr);
    });
    volatile size_t absurd = size_t(1) << 62;
    EXPECT_THROW(escaped = new char[absurd], std::bad_alloc);
    delete[] escaped;
    EXPECT_EQ(handlerCalls, 1);
    std::set_new_handler(nullptr);
}

}  // namespace
}  // namespace isotrace
