#pragma once

namespace isotrace {
inline constexpr const char* kVersion = "0.1.0";
}
