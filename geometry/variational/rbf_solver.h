// Fitting a variational implicit surface to its constraints: the dense
// symmetric system [A P; P^T 0][w; p] = [h; 0] of Turk and O'Brien, solved
// by projecting out the polynomial part (a QR of P) and a Cholesky
// factorisation of the rest, which is positive definite for distinct
// constraints not all in one plane because r^3 is conditionally positive
// definite of order 2.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/variational/constraints.h"
#include "geometry/variational/variational_field.h"

namespace isotrace::geometry {

/// A system that cannot be solved, with what makes it so.
class FitError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

struct FitOptions {
    /// Dense solves above this many unknowns are refused (with the memory
    /// they would need) rather than left to thrash: 20,000 unknowns take
    /// 3.2 GB.
    size_t maxUnknowns = 20000;
    /// The rendering domain: the constraints' box grown by this fraction of
    /// its diagonal on every side.
    double domainMargin = 0.1;
};

struct FitReport {
    size_t unknowns = 0;
    double seconds = 0.0;
    double maxResidual = 0.0;            ///< max |f(c_i) - h_i| (and gradient components)
    double reciprocalCondition = 0.0;    ///< estimate for the projected system
    std::vector<std::string> warnings;   ///< poor conditioning, large residual
};

/// Throws FitError for coincident constraints, constraints all in one plane
/// (or on a line), no non-zero constraint, or too many unknowns.
VariationalField fitVariationalField(const ConstraintSet& constraints, FitReport* report = nullptr,
                                     const FitOptions& options = {});

/// The checks fitVariationalField makes before solving: some value
/// constraint, finite numbers, not every value zero, no two constraints of
/// a kind at one place. Throws FitError.
void checkConstraints(const ConstraintSet& constraints);

/// The interpolant alone, for constraints already checked: no domain (left
/// empty), no residuals. Throws FitError when the system is singular (the
/// points in one plane, or too close for double precision).
VariationalField solveVariationalSystem(const ConstraintSet& constraints, double* reciprocalCondition = nullptr);

/// The size of what the constraints ask for, against which residuals are
/// judged: the largest |value| and |gradient| times the constraints' diagonal.
double constraintValueScale(const ConstraintSet& constraints);

/// Bytes a dense fit of this many unknowns needs.
double denseFitBytes(size_t unknowns);

}  // namespace isotrace::geometry
