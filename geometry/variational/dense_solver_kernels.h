// The dense Cholesky solve of a variational fit (rbf_solver.cpp), the cubic
// part of a fit's time: compiled once per instruction set
// (dense_solver_kernels.cpp, see geometry/instruction_set.h) and chosen at
// run time. Private to the library: not installed.
#pragma once

#include <cstddef>

namespace isotrace::geometry {

struct DenseSolverKernels {
    /// Factors the symmetric positive definite n x n matrix at `a`
    /// (column-major, columns `stride` apart; its lower triangle is read and
    /// overwritten by the factor, nothing else is touched) and solves
    /// a x = b in place of b. Returns false where the matrix is not positive
    /// definite; else *reciprocalCondition gets an estimate of 1 / cond_1.
    bool (*choleskySolve)(double* a, size_t n, size_t stride, double* b, double* reciprocalCondition);
};

/// The kernels of the active instruction set.
const DenseSolverKernels& denseSolverKernels();

namespace sse2 { extern const DenseSolverKernels kDenseSolverKernels; }
namespace avx2 { extern const DenseSolverKernels kDenseSolverKernels; }
namespace avx512 { extern const DenseSolverKernels kDenseSolverKernels; }

}  // namespace isotrace::geometry
