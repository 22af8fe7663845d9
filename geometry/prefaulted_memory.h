// Large arrays that are about to be written in full get their pages in one
// system call instead of one page fault each. Under virtualisation a first
// touch costs about 9 µs per 4 KiB page (measured on the 2-core benchmark
// machine, a Firecracker VM), populating a range about 0.6 µs per page.
// Simplifying the refined sphere of bench/polygonize_throughput alone took
// 0.31 s before and 0.22 s after; its whole adaptive polygonization by the
// command line, 0.386 s and 0.370 s (22,313 page faults and 13,882).
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace isotrace::geometry {

/// Asks the kernel to back the whole pages inside [data, data + bytes) now.
/// A hint only: nothing happens for small ranges (they lie in pages the
/// heap has touched already), on systems without MADV_POPULATE_WRITE, or
/// where it fails (kernels before 5.14).
inline void prefaultPages(void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    static const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
    if (bytes < 64 * page) return;
    const uintptr_t begin = (uintptr_t(data) + page - 1) & ~(page - 1);
    const uintptr_t end = (uintptr_t(data) + bytes) & ~(page - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#else
    (void)data;
    (void)bytes;
#endif
}

/// Room for n elements, its pages populated before the elements already
/// there move in.
template <class T>
void reservePrefaulted(std::vector<T>& v, size_t n) {
    if (v.capacity() < n) {
        std::vector<T> larger;
        larger.reserve(n);
        prefaultPages(larger.data(), n * sizeof(T));
        larger.insert(larger.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
        v.swap(larger);
    } else {
        prefaultPages(v.data(), n * sizeof(T));
    }
}

/// v.assign(n, value) into populated pages.
template <class T>
void assignPrefaulted(std::vector<T>& v, size_t n, const T& value) {
    reservePrefaulted(v, n);
    v.assign(n, value);
}

}  // namespace isotrace::geometry
