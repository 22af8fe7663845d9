// A 64-bit FNV-1a hash of bytes: a cache key and a "same input" check, not a
// cryptographic digest.
#pragma once

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>

namespace isotrace::geometry {

constexpr uint64_t kFnvOffsetBasis = 1469598103934665603ULL;

inline uint64_t fnv1a64(std::string_view bytes, uint64_t hash = kFnvOffsetBasis) {
    for (unsigned char c : bytes) {
        hash ^= c;
        hash *= 1099511628211ULL;
    }
    return hash;
}

/// The hash of a file's bytes continued from `hash`; false when unreadable.
inline bool fnv1a64File(const std::string& path, uint64_t& hash) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) hash = fnv1a64(std::string_view(buffer, size_t(in.gcount())), hash);
    return true;
}

inline std::string hexDigest(uint64_t hash) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

}  // namespace isotrace::geometry
