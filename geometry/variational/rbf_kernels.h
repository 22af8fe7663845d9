// The O(N) sums of a variational field's r^3 terms, w_i |x - c_i|^3, at a
// point: compiled once per instruction set (rbf_kernels.cpp, see
// geometry/instruction_set.h) and chosen at run time. Private to the library:
// not installed. Centres come as three coordinate arrays.
#pragma once

#include <cstddef>

namespace isotrace::geometry {

struct RbfTerms {
    const double *x, *y, *z, *weight;
    size_t count;
};

/// The value, gradient and Hessian terms' sums at a point, and sum |w_i|.
struct RbfTaylorSums {
    double value = 0, gradient[3] = {};
    double hxx = 0, hyy = 0, hzz = 0, hxy = 0, hxz = 0, hyz = 0;
    double absoluteWeights = 0;
};

struct RbfKernels {
    double (*value)(const RbfTerms& terms, const double* p);
    /// The value; the gradient's sums into gradient[3].
    double (*valueAndGradient)(const RbfTerms& terms, const double* p, double* gradient);
    void (*taylor)(const RbfTerms& terms, const double* p, RbfTaylorSums& sums);
    /// sum_i 6 |w_i| (the farthest distance from c_i to the box lo..hi).
    double (*hessianBound)(const RbfTerms& terms, const double* lo, const double* hi);
};

/// The kernels of the active instruction set.
const RbfKernels& rbfKernels();

namespace sse2 { extern const RbfKernels kRbfKernels; }
namespace avx2 { extern const RbfKernels kRbfKernels; }
namespace avx512 { extern const RbfKernels kRbfKernels; }

}  // namespace isotrace::geometry
