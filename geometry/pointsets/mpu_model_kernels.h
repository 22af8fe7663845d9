// The sums over an MPU numerator model's single-piece locals (its Taylor
// terms at a box's centre and their share of the error bounds over the box),
// compiled once per instruction set (mpu_model_kernels.cpp, see
// geometry/instruction_set.h) and chosen at run time. Private to the library:
// not installed.
#pragma once

#include <cstddef>

namespace isotrace::geometry {

/// The columns' order (MpuLocalColumns::Column in mpu_numerator_model.h).
struct MpuModelColumn {
    enum Column {
        CenterX, CenterY, CenterZ, Radius, InverseRadius2,
        OriginX, OriginY, OriginZ, Axx, Axy, Axz, Ayy, Ayz, Azz, Gx, Gy, Gz, C0,
        Curvature,
        kColumns
    };
};

/// Columns are padded with zeros to a multiple of this many locals: the
/// widest kernel's lanes (the padding's lanes are masked).
inline constexpr size_t kMpuModelColumnPadding = 8;

/// The single-piece locals' sums (see sumSingles in mpu_numerator_model.cpp).
struct MpuColumnSums {
    double value = 0.0, gradient[3] = {}, hessian[6] = {};  ///< hessian: xx xy xz yy yz zz
    double scale = 0.0;
    /// M3's shares: the sum of the locals' own bounds; N's third derivatives
    /// at the centre (xxx xxy xxz xyy xyz xzz yyy yyz yzz zzz) and the bound
    /// on the fourth over the box of the locals taken from the centre; the
    /// own bounds of the others.
    double ownThird = 0.0, tensor[10] = {}, fourth = 0.0, apart = 0.0;
    /// Of the others, those whose rim crosses the box and whose weight
    /// stays small over it: their own bounds (part of `apart`), and their
    /// errors bounded directly.
    double directOwn = 0.0, directValue = 0.0, directSlope = 0.0, directHessian = 0.0;
};

struct MpuModelKernels {
    /// The sums of `count` locals whose columns start at `columns`, `stride`
    /// apart, at the point c; with a box (lower and upper; lower null for
    /// none) of half diagonal rho, also the bounds' shares over it.
    void (*sumColumns)(const double* columns, size_t stride, size_t count, const double* c, const double* lower,
                       const double* upper, double rho, MpuColumnSums& sums);
};

/// The kernels of the active instruction set.
const MpuModelKernels& mpuModelKernels();

namespace sse2 { extern const MpuModelKernels kMpuModelKernels; }
namespace avx2 { extern const MpuModelKernels kMpuModelKernels; }
namespace avx512 { extern const MpuModelKernels kMpuModelKernels; }

}  // namespace isotrace::geometry
