#include "renderer/platform/embree_errors.h"

#include <new>

#include "geometry/errors.h"

namespace isotrace {

void EmbreeErrorRecord::attachTo(RTCDevice device) { rtcSetDeviceErrorFunction(device, record, this); }

void EmbreeErrorRecord::record(void* self, RTCError code, const char* message) {
    auto* r = static_cast<EmbreeErrorRecord*>(self);
    const std::lock_guard<std::mutex> lock(r->mutex_);
    if (r->code_ != RTC_ERROR_NONE) return;  // the first error is the cause
    r->code_ = code;
    r->message_ = message ? message : "";
}

void EmbreeErrorRecord::check(const char* during) {
    RTCError code;
    std::string message;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        code = code_;
        message.swap(message_);
        code_ = RTC_ERROR_NONE;
    }
    if (code == RTC_ERROR_NONE) return;
    if (code == RTC_ERROR_OUT_OF_MEMORY) throw std::bad_alloc();
    throw geometry::InternalError("Embree error " + std::to_string(int(code)) + " while " + during + ": " + message);
}

}  // namespace isotrace
