// The dense Cholesky solve (dense_solver_kernels.h) for one instruction set:
// compiled once per set by geometry/CMakeLists.txt (isotrace_isa_kernels).
// Eigen's blocked factorisation is what gains from wider vectors (a
// 10,000-unknown system factors several times faster with AVX2 and FMA than
// with SSE2), and its templates are inline functions that every other file
// instantiates too: here they are compiled in a namespace of this set's own,
// `Eigen` being renamed before its headers are read, so that no file shares
// a definition with this one (the test IsaKernelSymbols checks the objects).
#ifndef ISOTRACE_ISA
#error "compiled through isotrace_isa_kernels, which names the instruction set"
#endif

#define ISOTRACE_JOIN2(a, b) a##b
#define ISOTRACE_JOIN(a, b) ISOTRACE_JOIN2(a, b)
#define Eigen ISOTRACE_JOIN(isotrace_eigen_, ISOTRACE_ISA)
#include <Eigen/Cholesky>

#include "geometry/variational/dense_solver_kernels.h"

namespace isotrace::geometry::ISOTRACE_ISA {

namespace {

bool choleskySolve(double* a, size_t n, size_t stride, double* b, double* reciprocalCondition) {
    using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic>;
    using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1>;
    Eigen::Map<Matrix, Eigen::Unaligned, Eigen::OuterStride<>> matrix(a, Eigen::Index(n), Eigen::Index(n),
                                                                       Eigen::OuterStride<>(Eigen::Index(stride)));
    Eigen::Ref<Matrix> block(matrix);
    const Eigen::LLT<Eigen::Ref<Matrix>> llt(block);
    if (llt.info() != Eigen::Success) return false;
    *reciprocalCondition = llt.rcond();
    Eigen::Map<Vector> rhs(b, Eigen::Index(n));
    llt.solveInPlace(rhs);
    return true;
}

}  // namespace

extern const DenseSolverKernels kDenseSolverKernels = {choleskySolve};

}  // namespace isotrace::geometry::ISOTRACE_ISA
