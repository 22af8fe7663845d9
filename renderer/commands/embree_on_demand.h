// Embree loaded by the executable on demand (embree_on_demand.cpp): the
// executable does not link it, so that processes that trace no rays never
// pay for it and those that do load it beside their other start-up work.
#pragma once

namespace isotrace {

/// Starts loading Embree on a thread of its own, once; the first Embree
/// call (rtcNewDevice) waits for it, and starts it if nothing did.
void startLoadingEmbree();

/// Waits for a load started by startLoadingEmbree, if any: the process must
/// not exit during one (exit's destructors and a library's constructors
/// running side by side corrupted the heap in 1% of quick exits).
void finishLoadingEmbree();

}  // namespace isotrace
