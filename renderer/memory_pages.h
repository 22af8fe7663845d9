// Backing a freshly allocated buffer with memory before it is written.
//
// On a virtual machine every first touch of a 4 KB page traps to the
// hypervisor: a 640x480 colour buffer is 900 such traps, about 10 ms, which
// was a fifth of a small Whitted render. Asked for in one call, the kernel
// fills the range without trapping, in 2 MB pages where it may.
#pragma once

#include <cstddef>
#include <vector>

namespace isotrace {

/// Keeps freed blocks of up to 32 MB, and up to 256 MB of freed heap, in
/// the process for reuse; called once at start-up. By default glibc gives blocks above 128 KB back to the
/// kernel when freed, so every compressor state and line buffer OpenEXR
/// allocated was fresh pages again (1,150 page faults writing a 640x480
/// EXR; 460 now).
void keepFreedMemoryForReuse();

/// Gives the heap's freed memory back to the kernel when it is large (over
/// 64 MB), as building a large surface's cells leaves it: the scratch of a
/// million MPU parts was 170 MB still resident while Embree built its tree
/// and the frame rendered. Small scenes keep theirs for reuse.
void releaseLargeFreedMemory();

/// Asks for the whole pages of [data, data + bytes) to be backed by 2 MB
/// pages when first touched (transparent huge pages in "madvise" mode, as
/// Debian and most distributions set them): one fault per 2 MB instead of
/// 512. Only advice; nothing happens where the kernel has them disabled.
void adviseHugePages(void* data, size_t bytes);

/// Asks for [data, data + bytes) to be backed now, in huge pages where the
/// system allows them. Only advice: where the kernel refuses, pages are
/// faulted in on first touch as before.
void populatePages(void* data, size_t bytes);

/// `values` resized to `count` zeros, its memory populated first when it is
/// newly allocated.
template <typename T>
void assignZeros(std::vector<T>& values, size_t count) {
    values.clear();
    if (values.capacity() < count) {
        std::vector<T>().swap(values);
        values.reserve(count);
        populatePages(values.data(), count * sizeof(T));
    }
    values.assign(count, T(0));
}

}  // namespace isotrace
