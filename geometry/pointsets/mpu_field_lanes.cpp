// The single-piece locals' share of an MPU field's sums over a tracer's
// list, Lanes::size() locals at a time: gathered from the field's lane table
// (each quadric taken about its ball's centre, so one offset r serves the
// weight and the quadric). Built for the machine's widest vectors.
#include <algorithm>

#include "geometry/lanes.h"
#include "geometry/pointsets/mpu_field.h"

namespace isotrace::geometry {

namespace {

using std::experimental::reduce;

// Calls visit(load, valid) for each run of Lanes::size() locals of
// `singles`: load(column) gathers that column of the lane table; lanes past
// the list's end repeat its first local and are not valid.
template <class Visit>
void forLaneRuns(const std::vector<double>& table, size_t stride, std::span<const uint32_t> singles, Visit&& visit) {
    constexpr size_t kWidth = Lanes::size();
    const Lanes lane([](auto j) { return double(j); });
    for (size_t first = 0; first < singles.size(); first += kWidth) {
        const size_t count = std::min(kWidth, singles.size() - first);
        uint32_t index[kWidth];
        for (size_t j = 0; j < kWidth; ++j) index[j] = singles[first + (j < count ? j : 0)];
        auto load = [&](int column) {
            const double* values = table.data() + size_t(column) * stride;
            return Lanes([&](auto j) { return values[index[j]]; });
        };
        visit(load, lane < double(count));
    }
}

}  // namespace

void MpuField::addSingleLanes(const Vec3& p, std::span<const uint32_t> singles, MpuBlendSums& s) const {
    Lanes W = 0.0, N = 0.0, wx = 0.0, wy = 0.0, wz = 0.0, nx = 0.0, ny = 0.0, nz = 0.0;
    forLaneRuns(laneTable_, locals_.size(), singles, [&](auto&& load, const Lanes::mask_type& valid) {
        const Lanes rx = p.x() - load(CenterX), ry = p.y() - load(CenterY), rz = p.z() - load(CenterZ);
        const Lanes inverseR2 = load(InverseRadius2);
        const Lanes s1 = 1.0 - (rx * rx + ry * ry + rz * rz) * inverseR2;
        const Lanes::mask_type inside = valid && s1 > 0.0;
        if (none_of(inside)) return;  // no ball holds p: the quadrics are not needed
        const Lanes sigma = select(inside, s1, Lanes(0.0)), w = sigma * sigma * sigma;
        const Lanes axx = load(Axx), axy = load(Axy), axz = load(Axz), ayy = load(Ayy), ayz = load(Ayz),
                    azz = load(Azz);
        const Lanes arx = axx * rx + axy * ry + axz * rz, ary = axy * rx + ayy * ry + ayz * rz,
                    arz = axz * rx + ayz * ry + azz * rz;
        const Lanes gx = load(Gx), gy = load(Gy), gz = load(Gz);
        const Lanes q = load(C0) + (gx * rx + gy * ry + gz * rz) + (rx * arx + ry * ary + rz * arz);
        const Lanes dw = -6.0 * sigma * sigma * inverseR2;  // grad w = dw r
        W += w;
        N += w * q;
        wx += dw * rx;
        wy += dw * ry;
        wz += dw * rz;
        nx += dw * rx * q + w * (gx + 2.0 * arx);
        ny += dw * ry * q + w * (gy + 2.0 * ary);
        nz += dw * rz * q + w * (gz + 2.0 * arz);
    });
    s.W += reduce(W);
    s.N += reduce(N);
    s.gradientW += Vec3(reduce(wx), reduce(wy), reduce(wz));
    s.gradientN += Vec3(reduce(nx), reduce(ny), reduce(nz));
}

double MpuField::singleLanesNumerator(const Vec3& p, std::span<const uint32_t> singles) const {
    Lanes N = 0.0;
    forLaneRuns(laneTable_, locals_.size(), singles, [&](auto&& load, const Lanes::mask_type& valid) {
        const Lanes rx = p.x() - load(CenterX), ry = p.y() - load(CenterY), rz = p.z() - load(CenterZ);
        const Lanes s1 = 1.0 - (rx * rx + ry * ry + rz * rz) * load(InverseRadius2);
        const Lanes::mask_type inside = valid && s1 > 0.0;
        if (none_of(inside)) return;
        const Lanes sigma = select(inside, s1, Lanes(0.0));
        const Lanes axx = load(Axx), axy = load(Axy), axz = load(Axz), ayy = load(Ayy), ayz = load(Ayz),
                    azz = load(Azz);
        const Lanes q = load(C0) + (load(Gx) * rx + load(Gy) * ry + load(Gz) * rz) +
                        (rx * (axx * rx + axy * ry + axz * rz) + ry * (axy * rx + ayy * ry + ayz * rz) +
                         rz * (axz * rx + ayz * ry + azz * rz));
        N += sigma * sigma * sigma * q;
    });
    return reduce(N);
}

}  // namespace isotrace::geometry
