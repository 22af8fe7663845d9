// The sums over an MPU field's single-piece locals that run in vector lanes,
// compiled once per instruction set (mpu_lane_kernels.cpp, see
// geometry/instruction_set.h) and chosen at run time. Private to the library:
// not installed.
//
// Rows are kMpuLaneColumns doubles, 64-byte aligned, one per one-piece term:
// the ball's centre, 1 / R^2, and the quadric about the centre,
// Q = c0 + g . r + r^T A r with r = x - centre.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace isotrace::geometry {

enum MpuLaneColumn { CenterX, CenterY, CenterZ, InverseRadius2, C0, Gx, Gy, Gz, Axx, Axy, Axz, Ayy, Ayz, Azz };
inline constexpr size_t kMpuLaneColumns = 16;  ///< two cache lines a row (14 used)

/// One row.
struct alignas(64) MpuLaneRow {
    double values[kMpuLaneColumns] = {};
};

/// An MPU field's rows (MpuField's sumRows_): each single-piece local's,
/// indexed by local (zero rows for the others), then each piece of each
/// sharp local, which a tracer's list may resolve to one.
struct MpuSumRows {
    std::vector<MpuLaneRow> rows;
    std::vector<uint32_t> sharpPieceRows;  ///< per sharp local, the row of its first piece
};

/// W = sum w_i, N = sum w_i Q_i and their gradients.
struct MpuLaneSums {
    double W = 0, N = 0;
    double gradientW[3] = {}, gradientN[3] = {};
};

/// Receives a term w_i Q_i along a segment, u in [enter, leave]: nine
/// monomial coefficients of degree 0 to 8.
using MpuPartialTerm = void (*)(void* context, const double* monomials, double enter, double leave);

struct MpuLaneKernels {
    /// Adds the listed rows' terms at p to `sums`.
    void (*addSums)(const double* rows, const uint32_t* listed, size_t count, const double* p, MpuLaneSums& sums);
    /// N alone.
    double (*numerator)(const double* rows, const uint32_t* listed, size_t count, const double* p);
    /// The listed rows' terms along p0 + u D, u in [0, 1]: those whose ball
    /// holds the whole segment added to `whole` (nine monomials), the others
    /// handed to `partial`. Returns how many balls the segment meets.
    int (*alongSegment)(const double* rows, const uint32_t* listed, size_t count, const double* p0, const double* D,
                        double* whole, MpuPartialTerm partial, void* context);
};

/// The kernels of the active instruction set.
const MpuLaneKernels& mpuLaneKernels();

namespace sse2 { extern const MpuLaneKernels kMpuLaneKernels; }
namespace avx2 { extern const MpuLaneKernels kMpuLaneKernels; }
namespace avx512 { extern const MpuLaneKernels kMpuLaneKernels; }

}  // namespace isotrace::geometry
