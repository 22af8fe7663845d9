// The isotrace executable's global operator new: blocks of 2 MB and more
// (meshes, the simplifier's and refiner's arrays, marching cubes' output)
// are advised into transparent huge pages.
//
// On a virtual machine every first touch of a 4 KB page traps to the
// hypervisor, about 10 us. `isotrace polygonize` of a sphere at 256^3
// touched 40,000 fresh pages, a third of its run; with this it touches
// half as many and runs 1.3x faster. Over-aligned blocks (the simplifier's
// 64-byte records of vertex fans, 16 MB on that sphere) go through the
// aligned forms: advising them too took the simplification 0.216 s -> 0.199 s
// (medians of 5, 2026-12-05).
// Part of the executable only, not of the libraries: how a process uses
// memory is the application's choice, and a host of the geometry library
// keeps its own.
#include "renderer/commands/large_allocations.h"

#include <algorithm>
#include <cstdlib>
#include <new>

#include "renderer/memory_pages.h"

#if ISOTRACE_HUGE_PAGE_OPERATOR_NEW

namespace {
/// One huge page: smaller blocks could not use one.
constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

// `allocate` until it succeeds, calling the new handler between tries, as
// the standard's operator new does; large blocks advised into huge pages.
template <class Allocate>
void* allocateAdvised(std::size_t bytes, Allocate allocate) {
    for (;;) {
        if (void* p = allocate()) {
            if (bytes >= kHugePageBytes) isotrace::adviseHugePages(p, bytes);
            return p;
        }
        std::new_handler handler = std::get_new_handler();
        if (handler == nullptr) throw std::bad_alloc();
        handler();
    }
}
}  // namespace

// The array, nothrow and sized forms call these by default ([new.delete]).
void* operator new(std::size_t bytes) {
    return allocateAdvised(bytes, [&] { return std::malloc(bytes == 0 ? 1 : bytes); });
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

// Over-aligned types (the simplifier's cache-line records of vertex fans)
// come through these.
void* operator new(std::size_t bytes, std::align_val_t alignment) {
    const std::size_t a = std::max(std::size_t(alignment), sizeof(void*));
    return allocateAdvised(bytes, [&] {
        void* p = nullptr;
        return posix_memalign(&p, a, bytes == 0 ? 1 : bytes) == 0 ? p : nullptr;
    });
}

void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

#endif
