#include "renderer/memory_pages.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace isotrace {

namespace {

// Linux 5.14 and later; older kernels refuse it and the pages fault in as usual.
#ifndef MADV_POPULATE_WRITE
constexpr int MADV_POPULATE_WRITE = 23;
#endif

// Blocks up to this size come from the heap and return to it when freed;
// above it, mmap, and freed blocks go back to the kernel at once. 32 MB is
// the most glibc accepts. Polygonization's arrays (the simplifier's
// quadrics and vertex fans, the refiner's faces) are 5 to 20 MB: with 4 MB
// here every one was fresh pages, at 5-10 us per 4 KB page on a virtual
// machine; the adaptive sphere of bench/polygonize_throughput touched 6,400
// fresh pages per run, and 210 with these limits.
constexpr int kHeapBlockLimit = 32 << 20;
// The heap's free top is returned to the kernel only above this (at 64 MB
// the adaptive sphere still touched 1,100 fresh pages per run).
constexpr int kHeapTrimThreshold = 256 << 20;

// Small buffers are not worth a system call.
constexpr size_t kMinimumBytes = size_t(1) << 20;

// The whole pages inside [data, data + bytes), or none: advice applies to
// whole pages, and the allocator's neighbours in a partial page must not be
// disturbed.
bool wholePages(void* data, size_t bytes, uintptr_t& first, uintptr_t& last) {
    if (data == nullptr) return false;
    static const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
    first = (uintptr_t(data) + page - 1) & ~(page - 1);
    last = (uintptr_t(data) + bytes) & ~(page - 1);
    return last > first;
}

}  // namespace

void keepFreedMemoryForReuse() {
    mallopt(M_MMAP_THRESHOLD, kHeapBlockLimit);
    mallopt(M_TRIM_THRESHOLD, kHeapTrimThreshold);
}

void releaseLargeFreedMemory() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 33)
    constexpr size_t kLarge = size_t(64) << 20;
    if (mallinfo2().fordblks > kLarge) malloc_trim(0);
#endif
}

void adviseHugePages(void* data, size_t bytes) {
    if (uintptr_t first, last; wholePages(data, bytes, first, last))
        madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

void populatePages(void* data, size_t bytes) {
    if (bytes < kMinimumBytes) return;
    adviseHugePages(data, bytes);
    if (uintptr_t first, last; wholePages(data, bytes, first, last))
        madvise(reinterpret_cast<void*>(first), last - first, MADV_POPULATE_WRITE);
}

}  // namespace isotrace
