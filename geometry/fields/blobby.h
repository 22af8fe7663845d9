// Blobby objects (Blinn), metaballs (Nishimura), soft objects (Wyvill) and
// the (1 - a^2)^3 falloff:
// f(p) = T - sum_i w_i k(r_i(p) / R_i), negative where the blobs' sum
// exceeds the threshold T. r_i is the distance to the blob's centre, or,
// for a shaped blob (Blender's metaball elements), the distance in the
// blob's own frame to a segment, rectangle or box about its centre. Every
// kernel here has finite support, so a cell keeps only the blobs that reach
// it (prunedTo) and stays exact.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

enum class BlobKernel {
    Blinn,      ///< exp(-b a^2), truncated smoothly where it falls below e^-36
    Metaball,   ///< Nishimura's piecewise quadratic, support a <= 1
    SoftObject,  ///< Wyvill's sextic, support a <= 1
    Poly6        ///< (1 - a^2)^3, support a <= 1: SPH's poly6, Segment Tracing's falloff
};

/// The frame and core of a shaped blob: r(p) is the distance from
/// q = toLocal (p - c) to the box [-halfSize, halfSize] (a point, segment,
/// rectangle or box as its sizes are zero or not).
struct BlobShape {
    Mat3 toLocal = Mat3::Identity();
    Vec3 halfSize = Vec3::Zero();
    double stretch = 1.0;  ///< largest singular value of toLocal: r's Lipschitz bound
};

inline constexpr uint32_t kRoundBlob = ~0u;

struct Blob {
    Vec3 center = Vec3::Zero();
    double radius = 1.0;
    double weight = 1.0;
    uint32_t shape = kRoundBlob;  ///< index into BlobbyField::shapes, or a ball
};

struct BlobbyField {
    BlobKernel kernel = BlobKernel::Metaball;
    double threshold = 0.5;
    double blobbiness = 4.0;  ///< b of the Blinn kernel
    std::vector<Blob> blobs;
    /// Shared by the field's pruned copies (cells copy blobs, not shapes).
    std::shared_ptr<const std::vector<BlobShape>> shapes;

    /// Kernel and its derivative in the normalised radius a = r / R.
    double kernelValue(double a) const;
    double kernelSlope(double a) const;
    /// Largest |dk/da| over [a0, a1].
    double maxKernelSlope(double a0, double a1) const;
    /// a beyond which the kernel is zero.
    double support() const;

    /// r of one blob, with its gradient; its range and Lipschitz bound over a box.
    double distanceTo(const Blob& b, const Vec3& p) const;
    double distanceTo(const Blob& b, const Vec3& p, Vec3& gradient) const;
    Interval distanceRange(const Blob& b, const Box3& box) const;
    double distanceLipschitz(const Blob& b) const;
    /// The gradient of one blob's term w k(r / R) (the field's is minus their sum).
    Vec3 termGradient(const Blob& b, const Vec3& p) const;

    double value(const Vec3& p) const;
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    Interval range(const Box3& box) const;
    double lipschitz(const Box3& box) const;
    Box3 bounds() const;
    /// The same field restricted to the blobs whose support reaches `box`.
    BlobbyField prunedTo(const Box3& box) const;
    size_t termCount() const { return blobs.size(); }
};

}  // namespace isotrace::geometry
