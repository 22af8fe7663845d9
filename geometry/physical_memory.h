// The machine's physical memory, against which inputs that would allocate
// in proportion to a user's numbers (resolutions, voxel sizes, grids) are
// refused before allocating.
#pragma once

#include <unistd.h>

namespace isotrace::geometry {

inline double physicalMemoryBytes() { return double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE)); }

}  // namespace isotrace::geometry
