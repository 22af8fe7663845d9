// Embree reports errors through a C callback, and an exception must not
// unwind through Embree's C frames. The callback records the first error
// instead, and the caller checks the record after the Embree calls that
// may raise it.
#pragma once

#include <embree3/rtcore.h>

#include <mutex>
#include <string>

namespace isotrace {

class EmbreeErrorRecord {
public:
    /// Sends `device`'s errors here; the record must outlive the device.
    void attachTo(RTCDevice device);
    /// Throws what Embree reported since the last check, naming `during`:
    /// std::bad_alloc when it ran out of memory, geometry::InternalError
    /// for the rest (isotrace called it wrongly). Then forgets it.
    void check(const char* during);

private:
    static void record(void* self, RTCError code, const char* message);

    std::mutex mutex_;  // Embree may report from any of its threads
    RTCError code_ = RTC_ERROR_NONE;
    std::string message_;
};

}  // namespace isotrace
