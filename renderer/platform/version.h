// The program's version and the numeric mode its renders are computed in,
// recorded in every render's metadata: `merge` refuses tiles that differ in
// either.
#pragma once

#ifndef ISOTRACE_VERSION
#error "renderer/CMakeLists.txt defines ISOTRACE_VERSION from the project's version"
#endif

namespace isotrace {

inline constexpr const char* kVersion = ISOTRACE_VERSION;

/// Every field sum in double precision, on every instruction set (the
/// vector kernels change the order of a sum, not its precision).
inline constexpr const char* kNumericMode = "double";

}  // namespace isotrace
