// Benchmarks allocate as the isotrace executable does: its operator new
// (renderer/commands/large_allocations.cpp, linked beside this) and, set
// here before main as its main sets it, its policy of keeping freed memory
// for reuse. Their figures are then the executable's.
#include "renderer/memory_pages.h"

namespace {
const bool kKeepsFreedMemory = (isotrace::keepFreedMemoryForReuse(), true);
}  // namespace
