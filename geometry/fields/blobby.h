// Blobby objects (Blinn), metaballs (Nishimura), soft objects (Wyvill) and
// the (1 - a^2)^3 falloff:
// f(p) = T - sum_i w_i k(|p - c_i| / R_i), negative where the blobs' sum
// exceeds the threshold T. Every kernel here has finite support, so a cell
// keeps only the blobs that reach it (prunedTo) and stays exact.
#pragma once

#include <vector>

#include "geometry/fields/distance_field_bounds.h"

namespace isotrace::geometry {

enum class BlobKernel {
    Blinn,      ///< exp(-b a^2), truncated smoothly where it falls below e^-36
    Metaball,   ///< Nishimura's piecewise quadratic, support a <= 1
    SoftObject,  ///< Wyvill's sextic, support a <= 1
    Poly6        ///< (1 - a^2)^3, support a <= 1: SPH's poly6, Segment Tracing's falloff
};

struct Blob {
    Vec3 center = Vec3::Zero();
    double radius = 1.0;
    double weight = 1.0;
};

struct BlobbyField {
    BlobKernel kernel = BlobKernel::Metaball;
    double threshold = 0.5;
    double blobbiness = 4.0;  ///< b of the Blinn kernel
    std::vector<Blob> blobs;

    /// Kernel and its derivative in the normalised radius a = r / R.
    double kernelValue(double a) const;
    double kernelSlope(double a) const;
    /// Largest |dk/da| over [a0, a1].
    double maxKernelSlope(double a0, double a1) const;
    /// a beyond which the kernel is zero.
    double support() const;

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
