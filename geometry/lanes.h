// Arithmetic written once for doubles and for vector lanes
// (std::experimental::simd): the few choices that differ between the two,
// so that a bound can be evaluated one value at a time or eight at a time
// by the same code.
#pragma once

#include <experimental/simd>
#include <type_traits>

namespace isotrace::geometry {

/// Doubles in the widest vector the file is compiled for.
using Lanes = std::experimental::native_simd<double>;

/// The first `count` lanes (a run of fewer locals than lanes). A template,
/// so that files compiled for other vector widths define no function of
/// the same name (geometry/instruction_set.h).
template <class L>
[[gnu::always_inline]] inline typename L::mask_type firstLanes(size_t count) {
    const L lane([](auto j) { return double(j); });
    return lane < double(count);
}

/// chosen ? a : b, lane by lane for vectors.
template <class Mask, class T>
[[gnu::always_inline]] inline T select(const Mask& chosen, const T& a, const T& b) {
    if constexpr (std::is_same_v<Mask, bool>) {
        return chosen ? a : b;
    } else {
#if defined(__clang__)
        // Clang 14 with libstdc++ 12 compiles the masked assignment below to
        // a no-op for AVX-512's bit masks (the MPU lane sums came out wrong
        // in the sanitizer build): lane by lane there. GCC's blend of the
        // masked assignment is 3% faster on an MPU render than this.
        return T([&](auto j) { return chosen[j] ? a[j] : b[j]; });
#else
        T r = b;
        where(chosen, r) = a;
        return r;
#endif
    }
}

/// std::min and std::max's choices (b only when strictly smaller or
/// larger), by value, for doubles and lanes alike.
template <class T>
[[gnu::always_inline]] inline T lesser(const T& a, const T& b) {
    return select(b < a, b, a);
}
template <class T>
[[gnu::always_inline]] inline T greater(const T& a, const T& b) {
    return select(a < b, b, a);
}

}  // namespace isotrace::geometry
