// MpuField's sums over single-piece locals, handed to the vector kernels of
// the active instruction set (mpu_lane_kernels.h).
#include "geometry/instruction_set.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/pointsets/mpu_lane_kernels.h"
#include "geometry/pointsets/mpu_weight_bounds.h"
#include "geometry/segment_polynomial.h"

namespace isotrace::geometry {

double mpuWeightSlope(const Interval& distance, double R) {
    return mpuWeightSlope<double>(distance.lo, distance.hi, R);
}

const MpuLaneKernels& mpuLaneKernels() {
    static const MpuLaneKernels& chosen =
        tableForActiveSet(sse2::kMpuLaneKernels, avx2::kMpuLaneKernels, avx512::kMpuLaneKernels);
    return chosen;
}

void MpuField::addOnePieceSums(const Vec3& p, std::span<const uint32_t> rows, MpuBlendSums& s) const {
    MpuLaneSums lanes;
    mpuLaneKernels().addSums(reinterpret_cast<const double*>(sumRows_->rows.data()), rows.data(), rows.size(), p.data(), lanes);
    s.W += lanes.W;
    s.N += lanes.N;
    s.gradientW += Vec3(lanes.gradientW[0], lanes.gradientW[1], lanes.gradientW[2]);
    s.gradientN += Vec3(lanes.gradientN[0], lanes.gradientN[1], lanes.gradientN[2]);
}

double MpuField::onePieceNumerator(const Vec3& p, std::span<const uint32_t> rows) const {
    return mpuLaneKernels().numerator(reinterpret_cast<const double*>(sumRows_->rows.data()), rows.data(), rows.size(), p.data());
}

int MpuField::addSinglesAlongSegment(const Vec3& p0, const Vec3& D, std::span<const uint32_t> singles,
                                     SegmentPolynomialSum<8>& sum) const {
    Monomials<8> whole{};
    auto partial = [](void* context, const double* monomials, double enter, double leave) {
        Monomials<8> poly;
        for (int k = 0; k <= 8; ++k) poly[k] = monomials[k];
        static_cast<SegmentPolynomialSum<8>*>(context)->add(poly, enter, leave);
    };
    const int met = mpuLaneKernels().alongSegment(reinterpret_cast<const double*>(sumRows_->rows.data()), singles.data(), singles.size(), p0.data(),
                                                  D.data(), whole.data(), partial, &sum);
    sum.add(whole, 0.0, 1.0);
    return met;
}

}  // namespace isotrace::geometry
