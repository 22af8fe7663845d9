#include "geometry/fields/blobby.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {
constexpr double kBlinnCutExponent = 36.0;  // e^-36 ~ 2e-16: below double round-off of k(0) = 1

// Peak of |k'(a)| for Wyvill's kernel: root of 120 a^4 - 204 a^2 + 44 in (0, 1).
const double kSoftObjectPeak = std::sqrt((204.0 - std::sqrt(204.0 * 204.0 - 4.0 * 120.0 * 44.0)) / 240.0);
// Peak of |k'(a)| = 6 a (1 - a^2)^2: its derivative 6 (1 - a^2)(1 - 5 a^2) vanishes at 1/sqrt(5).
const double kPoly6Peak = 1.0 / std::sqrt(5.0);
}  // namespace

double BlobbyField::support() const {
    return kernel == BlobKernel::Blinn ? std::sqrt(kBlinnCutExponent / blobbiness) : 1.0;
}

double BlobbyField::kernelValue(double a) const {
    switch (kernel) {
        case BlobKernel::Blinn: {
            const double cut = std::exp(-kBlinnCutExponent);
            return std::max(0.0, std::exp(-blobbiness * a * a) - cut) / (1.0 - cut);
        }
        case BlobKernel::Metaball:
            if (a <= 1.0 / 3.0) return 1.0 - 3.0 * a * a;
            if (a <= 1.0) return 1.5 * (1.0 - a) * (1.0 - a);
            return 0.0;
        case BlobKernel::SoftObject: {
            if (a >= 1.0) return 0.0;
            const double a2 = a * a, a4 = a2 * a2, a6 = a4 * a2;
            return 1.0 - (4.0 / 9.0) * a6 + (17.0 / 9.0) * a4 - (22.0 / 9.0) * a2;
        }
        case BlobKernel::Poly6: {
            if (a >= 1.0) return 0.0;
            const double u = 1.0 - a * a;
            return u * u * u;
        }
    }
    return 0.0;
}

double BlobbyField::kernelSlope(double a) const {
    switch (kernel) {
        case BlobKernel::Blinn: {
            if (a >= support()) return 0.0;
            const double cut = std::exp(-kBlinnCutExponent);
            return -2.0 * blobbiness * a * std::exp(-blobbiness * a * a) / (1.0 - cut);
        }
        case BlobKernel::Metaball:
            if (a <= 1.0 / 3.0) return -6.0 * a;
            if (a <= 1.0) return -3.0 * (1.0 - a);
            return 0.0;
        case BlobKernel::SoftObject: {
            if (a >= 1.0) return 0.0;
            const double a2 = a * a, a3 = a2 * a, a5 = a3 * a2;
            return -(24.0 / 9.0) * a5 + (68.0 / 9.0) * a3 - (44.0 / 9.0) * a;
        }
        case BlobKernel::Poly6: {
            if (a >= 1.0) return 0.0;
            const double u = 1.0 - a * a;
            return -6.0 * a * u * u;
        }
    }
    return 0.0;
}

double BlobbyField::maxKernelSlope(double a0, double a1) const {
    // |k'| rises to one peak and falls (each kernel), so the maximum over an
    // interval is at the peak when it lies inside, else at an end.
    double peak = 0.0;
    switch (kernel) {
        case BlobKernel::Blinn: peak = 1.0 / std::sqrt(2.0 * blobbiness); break;
        case BlobKernel::Metaball: peak = 1.0 / 3.0; break;
        case BlobKernel::SoftObject: peak = kSoftObjectPeak; break;
        case BlobKernel::Poly6: peak = kPoly6Peak; break;
    }
    if (a0 <= peak && peak <= a1) return std::abs(kernelSlope(peak));
    return std::max(std::abs(kernelSlope(a0)), std::abs(kernelSlope(a1)));
}

namespace {
// The offset from the shape's core box to q (zero inside the core).
Vec3 offsetFromCore(const BlobShape& shape, const Vec3& q) {
    return q - q.cwiseMax(-shape.halfSize).cwiseMin(shape.halfSize);
}
}  // namespace

double BlobbyField::distanceTo(const Blob& b, const Vec3& p) const {
    if (b.shape == kRoundBlob) return (p - b.center).norm();
    const BlobShape& shape = (*shapes)[b.shape];
    return offsetFromCore(shape, shape.toLocal * (p - b.center)).norm();
}

double BlobbyField::distanceTo(const Blob& b, const Vec3& p, Vec3& gradient) const {
    Vec3 offset = p - b.center;
    const BlobShape* shape = b.shape == kRoundBlob ? nullptr : &(*shapes)[b.shape];
    if (shape) offset = offsetFromCore(*shape, shape->toLocal * offset);
    const double r = offset.norm();
    gradient = Vec3::Zero();
    if (r > 0) gradient = shape ? Vec3(shape->toLocal.transpose() * offset / r) : Vec3(offset / r);
    return r;
}

Interval BlobbyField::distanceRange(const Blob& b, const Box3& box) const {
    if (b.shape == kRoundBlob) return box.distanceRange(b.center);
    if (!box.isFinite()) return {0.0, std::numeric_limits<double>::infinity()};
    // The box's image in the blob's frame, bounded by a box (interval
    // matrix product); r separates into one term per axis, so its extremes
    // over that box are the per-axis extremes.
    const BlobShape& shape = (*shapes)[b.shape];
    const Vec3 center = (shape.toLocal * (box.center() - b.center)).cwiseAbs();
    const Vec3 half = shape.toLocal.cwiseAbs() * (0.5 * box.extent());
    return {(center - half - shape.halfSize).cwiseMax(0.0).norm(), (center + half - shape.halfSize).cwiseMax(0.0).norm()};
}

double BlobbyField::distanceLipschitz(const Blob& b) const {
    return b.shape == kRoundBlob ? 1.0 : (*shapes)[b.shape].stretch;
}

Vec3 BlobbyField::termGradient(const Blob& b, const Vec3& p) const {
    Vec3 gradient;
    const double r = distanceTo(b, p, gradient);
    return (b.weight * kernelSlope(r / b.radius) / b.radius) * gradient;
}

double BlobbyField::value(const Vec3& p) const {
    double sum = 0.0;
    for (const Blob& b : blobs) sum += b.weight * kernelValue(distanceTo(b, p) / b.radius);
    return threshold - sum;
}

double BlobbyField::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    double sum = 0.0;
    gradient = Vec3::Zero();
    for (const Blob& b : blobs) {
        Vec3 distanceGradient;
        const double a = distanceTo(b, p, distanceGradient) / b.radius;
        sum += b.weight * kernelValue(a);
        gradient -= (b.weight * kernelSlope(a) / b.radius) * distanceGradient;
    }
    return threshold - sum;
}

Interval BlobbyField::range(const Box3& box) const {
    Interval sum(0.0);
    for (const Blob& b : blobs) {
        const Interval r = distanceRange(b, box);
        // Kernels decrease with distance.
        sum += b.weight * Interval(kernelValue(r.hi / b.radius), kernelValue(r.lo / b.radius));
    }
    return Interval(threshold) - sum;
}

double BlobbyField::lipschitz(const Box3& box) const {
    double sum = 0.0;
    for (const Blob& b : blobs) {
        const Interval r = distanceRange(b, box);
        sum += std::abs(b.weight) * maxKernelSlope(r.lo / b.radius, r.hi / b.radius) * distanceLipschitz(b) / b.radius;
    }
    return sum;
}

Box3 BlobbyField::bounds() const {
    // With T > 0 the field is positive wherever no positive blob reaches.
    if (threshold <= 0) return Box3::everything();
    Box3 box;
    for (const Blob& b : blobs) {
        if (b.weight <= 0) continue;
        const double reach = b.radius * support();
        if (b.shape == kRoundBlob) {
            box.extend(Box3::around(b.center, reach));
        } else {
            const BlobShape& shape = (*shapes)[b.shape];
            const Vec3 core = shape.halfSize + Vec3::Constant(reach);
            box.extend(transformBox(shape.toLocal.inverse(), b.center, Box3(-core, core)));
        }
    }
    return box;
}

BlobbyField BlobbyField::prunedTo(const Box3& box) const {
    // Kept: the blobs whose support reaches into the box. Counted first so
    // that the list is allocated once (cells are pruned by the thousand).
    auto reaches = [&](const Blob& b) {
        const double reach = b.radius * support();
        if (b.shape != kRoundBlob) return distanceRange(b, box).lo < reach;
        const Vec3 outside = (box.lower - b.center).cwiseMax(b.center - box.upper).cwiseMax(0.0);
        return outside.squaredNorm() < reach * reach;
    };
    BlobbyField out{kernel, threshold, blobbiness, {}, shapes};
    out.blobs.reserve(size_t(std::count_if(blobs.begin(), blobs.end(), reaches)));
    for (const Blob& b : blobs)
        if (reaches(b)) out.blobs.push_back(b);
    return out;
}

}  // namespace isotrace::geometry
