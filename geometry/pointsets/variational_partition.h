// Variational fits past the dense solver's limit (FitOptions::maxUnknowns):
// a partition of unity of local r^3 interpolants (Tobor, Reuter and Schlick
// 2004; Ohtake, Belyaev and Seidel 2004). An octree splits the constraints
// until each leaf holds a few dozen; each leaf's ball (support times its
// diagonal, grown until it holds enough constraints) gets the exact r^3
// interpolant of the constraints inside it, linear part included; the
// interpolants are blended by MPU's weights (1 - |x - c|^2 / R^2)^3.
//
// Every ball that reaches a constraint holds it, and every interpolant
// meets it there, so the blend interpolates every constraint as the dense
// fit does (up to the solves' rounding and MPU's faint background term).
// Between constraints it follows local thin-plate energies instead of one
// global one; bench/variational_fit measures the difference on the hand.
// The result is an MpuField whose locals are interpolants, so it renders,
// polygonizes, saves and loads as MPU fields do.
#pragma once

#include <string>
#include <vector>

#include "geometry/pointsets/mpu_field.h"
#include "geometry/variational/constraints.h"

namespace isotrace::geometry {

struct PartitionOptions {
    /// An octree cell splits while more constraints than this lie in it.
    int leafConstraints = 32;
    /// A ball short of this many constraints grows to hold its nearest this many.
    int ballConstraints = 64;
    /// Cells whose ball would hold more split too (a sparse cell beside a
    /// dense sheet): the local solve costs the cube of its size.
    int mostBallConstraints = 320;
    /// Ball radius over cell diagonal, as MpuOptions::support.
    double support = 0.75;
    int maxDepth = 16;
    /// The domain: the constraints' bounding cube grown by this fraction of
    /// their diagonal on every side (FitOptions::domainMargin).
    double domainMargin = 0.1;
};

struct PartitionReport {
    size_t constraints = 0;      ///< value and gradient constraints
    size_t locals = 0;           ///< interpolants
    size_t largestLocal = 0;     ///< constraints of the largest
    double meanLocal = 0.0;      ///< constraints per interpolant
    int depth = 0;
    double maxResidual = 0.0;    ///< of the blend at the constraints, as FitReport's
    double seconds = 0.0;
    std::vector<std::string> warnings;
};

/// Throws FitError (rbf_solver.h) for what the dense fit refuses
/// (coincident or non-finite constraints, none non-zero) and for a ball
/// whose constraints stay singular however far it grows.
MpuField fitPartitionedVariationalField(const ConstraintSet& constraints, PartitionReport* report = nullptr,
                                        const PartitionOptions& options = {});

}  // namespace isotrace::geometry
