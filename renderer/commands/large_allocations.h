// Whether this build's isotrace executable replaces operator new
// (large_allocations.cpp): not under sanitizers, which bring their own.
#pragma once

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ISOTRACE_HUGE_PAGE_OPERATOR_NEW 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define ISOTRACE_HUGE_PAGE_OPERATOR_NEW 0
#endif
#endif
#ifndef ISOTRACE_HUGE_PAGE_OPERATOR_NEW
#define ISOTRACE_HUGE_PAGE_OPERATOR_NEW 1
#endif

namespace isotrace {
inline constexpr bool kHugePageOperatorNew = ISOTRACE_HUGE_PAGE_OPERATOR_NEW;
}  // namespace isotrace
